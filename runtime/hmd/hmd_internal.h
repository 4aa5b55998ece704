/* @brief runtime/hmd's own helpers (not installed): one line of error text into a caller's buffer. */
#ifndef FV_HMD_INTERNAL_H
#define FV_HMD_INTERNAL_H

#include <stddef.h>

#include "fv_result.h"

/** printf into err (err_size bytes, NULL or 0: nothing). */
void fv_hmd_say(char *err, size_t err_size, const char *fmt, ...) FV_PRINTF(3, 4);

#endif
