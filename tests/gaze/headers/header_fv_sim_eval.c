#include "fv_sim_eval.h" /* compiles on its own */
