/* @brief fv_trace_driver.h compiles on its own. */
#include "fv_trace_driver.h"
