#include "fv_gaze_noise.h" /* compiles on its own */
