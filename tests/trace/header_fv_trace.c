/* @brief fv_trace.h compiles on its own. */
#include "fv_trace.h"
