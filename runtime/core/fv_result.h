/* @brief fv_result: the one result type of fovea. 0 success, positive non-errors, negative errors. */
#ifndef FV_RESULT_H
#define FV_RESULT_H

#if defined(__GNUC__) || defined(__clang__)
#define FV_MUST_CHECK __attribute__((warn_unused_result))
#define FV_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define FV_MUST_CHECK
#define FV_PRINTF(a, b)
#endif

typedef enum fv_result {
    FV_OK = 0,
    FV_TIMEOUT = 1,          /* nothing arrived before the timeout; try again */
    FV_NO_NEW_DATA = 2,      /* the call worked but had nothing new to give */
    FV_END_OF_STREAM = 3,    /* a finite source (a trace) has no more samples */
    FV_ERR_INVALID_ARG = -1, /* a caller passed something the contract forbids */
    FV_ERR_NO_MEMORY = -2,   /* an allocation failed or a budget was exceeded */
    FV_ERR_IO = -3,          /* a file or device operation failed at the OS level */
    FV_ERR_PROTOCOL = -4,    /* a device sent bytes that break its declared protocol */
    FV_ERR_PARSE = -5,       /* a file or string is malformed (the log says where and why) */
    FV_ERR_VULKAN = -6,      /* a Vulkan call failed (the log names the call and VkResult) */
    FV_ERR_DEVICE_LOST = -7, /* the device went away (unplugged, hung up, GPU lost) */
    FV_ERR_UNSUPPORTED = -8, /* the request is valid but this build/device cannot do it */
    FV_ERR_NOT_FOUND = -9,   /* a named thing (file, device, preset, scene) does not exist */
    FV_ERR_RANGE = -10,      /* a value is outside its allowed range (NaN, negative, too large) */
    FV_ERR_STATE = -11,      /* the object is not in a state that allows this call */
    FV_ERR_CANCELLED = -12,  /* the caller asked the work to stop (Ctrl-C); nothing was produced */
} fv_result;

/** Static name of a result code ("FV_ERR_PARSE"); never NULL. */
const char *fv_result_str(fv_result r);

#define FV_FAILED(r) ((r) < 0)

/** Propagate an error: evaluate, return it from the caller if it is an error. */
#define FV_TRY(expr)                                                                                                   \
    do {                                                                                                               \
        fv_result fv_try_r_ = (expr);                                                                                  \
        if (fv_try_r_ < 0) return fv_try_r_;                                                                           \
    } while (0)

#endif
