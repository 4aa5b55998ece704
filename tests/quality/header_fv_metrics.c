/* @brief fv_metrics.h compiles on its own. */
#include "fv_metrics.h"
