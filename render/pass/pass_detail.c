/* @brief Named numbers a pass reports about its last frame (see fv_plan.h). */
#include <stdio.h>
#include <string.h>

#include "fv_plan.h"

uint32_t fv_pass_detail_add(fv_pass_detail *out, uint32_t n, uint32_t cap, const char *key, uint32_t count, double a,
                            double b, double c)
{
    if (!out || n >= cap) return n;
    memset(&out[n], 0, sizeof out[n]);
    snprintf(out[n].key, sizeof out[n].key, "%s", key ? key : "");
    out[n].value[0] = a;
    out[n].value[1] = b;
    out[n].value[2] = c;
    out[n].count = count <= 3 ? count : 3;
    return n + 1;
}
