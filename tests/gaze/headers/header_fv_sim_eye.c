#include "fv_sim_eye.h" /* compiles on its own */
