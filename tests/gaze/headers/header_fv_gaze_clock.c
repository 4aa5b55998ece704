#include "fv_gaze_clock.h" /* compiles on its own */
