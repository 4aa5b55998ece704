#include "fv_gaze_unwrap.h" /* compiles on its own */
