/* @brief A shared object that is no driver plug-in (no fv_driver_plugin): FOVEA_DRIVERS must skip it with one line. */
int fv_test_not_a_plugin(void);
int fv_test_not_a_plugin(void) { return 1; }
