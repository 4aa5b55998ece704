/* @brief fv_reference.h compiles on its own. */
#include "fv_reference.h"
