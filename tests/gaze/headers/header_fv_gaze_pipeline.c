#include "fv_gaze_pipeline.h" /* compiles on its own */
