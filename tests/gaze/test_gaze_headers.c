/* @brief Each public header of runtime/gaze and sim/gaze compiles on its own (headers/header_*.c, one line each). */
#include "fv_test.h"

static void gaze_headers_compile_alone(void **state)
{
    (void)state; /* the check is that this executable built */
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(gaze_headers_compile_alone)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
