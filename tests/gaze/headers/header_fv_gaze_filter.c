#include "fv_gaze_filter.h" /* compiles on its own */
