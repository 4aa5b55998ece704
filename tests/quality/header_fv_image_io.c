/* @brief fv_image_io.h compiles on its own. */
#include "fv_image_io.h"
