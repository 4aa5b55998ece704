/* @brief A fake Pupil Capture for the pupil driver's tests: Pupil Remote (REP: SUB_PORT, t, v) and a gaze publisher
 * (XPUB, so it knows when the driver has subscribed) replaying a script of messages at host times, both on
 * loopback, each on its own thread. The Pupil clock is host time plus a fixed offset. */
#ifndef FV_TEST_FAKE_CAPTURE_H
#define FV_TEST_FAKE_CAPTURE_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <pthread.h>

typedef struct fake_msg {
    char topic[32];
    unsigned char *payload; /* owned; NULL with single_frame */
    size_t len;
    bool single_frame;      /* send the topic frame only (malformed) */
    int64_t due_pupil_ns;   /* publish when the fake's Pupil clock reaches this */
} fake_msg;

typedef struct fake_capture {
    void *ctx, *rep, *pub;
    int remote_port, sub_port;
    int64_t offset_ns; /* pupil = host + offset */
    pthread_t rep_thread, pub_thread;
    bool rep_running, pub_running;
    atomic_bool stop;
    atomic_int subscribed, published;
    const fake_msg *script;
    size_t script_len;
    /* Pupil Remote's answer to `t` (set after start, before the driver asks): t_reply_len bytes of t_reply instead
     * of the time when t_reply is set; answered only after t_delay_ms when that is > 0 (too late: no answer). */
    const char *t_reply;
    size_t t_reply_len;
    int t_delay_ms;
    atomic_int t_requests; /* `t` requests answered so far */
} fake_capture;

/** Start Pupil Remote on remote_port (0 = any free port) with the Pupil clock at pupil_now_ns now. */
int fake_capture_start(fake_capture *f, int remote_port, int64_t pupil_now_ns);
/** Publish the script (borrowed) once the driver has subscribed, each message at its due Pupil time. */
int fake_capture_play(fake_capture *f, const fake_msg *script, size_t n);
/** Wait until the whole script is out (or timeout_ms). 1 when done. */
int fake_capture_wait_played(fake_capture *f, int timeout_ms);
/** Stop both threads and close every socket (Capture quits). */
void fake_capture_stop(fake_capture *f);
/** The fake's Pupil clock now. */
int64_t fake_capture_pupil_now_ns(const fake_capture *f);

#endif
