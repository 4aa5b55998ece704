/* @brief fv_pupil_driver.h compiles on its own. */
#include "fv_pupil_driver.h"
