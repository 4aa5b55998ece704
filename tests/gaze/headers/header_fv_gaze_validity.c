#include "fv_gaze_validity.h" /* compiles on its own */
