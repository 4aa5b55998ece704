#include "fv_sim_driver.h" /* compiles on its own */
