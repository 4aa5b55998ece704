#include "fv_gaze_saccade.h" /* compiles on its own */
