/* @brief The fake Pupil Capture of the pupil driver's tests (see fake_capture.h). */
#include "fake_capture.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <zmq.h>

#include "fv_clock.h"

static int bound_port(void *s)
{
    char ep[128];
    size_t n = sizeof ep;
    if (zmq_getsockopt(s, ZMQ_LAST_ENDPOINT, ep, &n) != 0) return -1;
    const char *c = strrchr(ep, ':');
    return c ? atoi(c + 1) : -1;
}

int64_t fake_capture_pupil_now_ns(const fake_capture *f) { return fv_time_monotonic_ns() + f->offset_ns; }

static void sleep_ns(int64_t ns)
{
    if (ns <= 0) return;
    struct timespec ts = {(time_t)(ns / 1000000000), (long)(ns % 1000000000)};
    nanosleep(&ts, NULL);
}

static void *rep_main(void *arg)
{
    fake_capture *f = arg;
    while (!atomic_load(&f->stop)) {
        zmq_pollitem_t it = {f->rep, 0, ZMQ_POLLIN, 0};
        if (zmq_poll(&it, 1, 10) <= 0) continue;
        char req[64];
        int n = zmq_recv(f->rep, req, sizeof req - 1, 0);
        if (n < 0) continue;
        req[n < (int)sizeof req - 1 ? n : (int)sizeof req - 1] = '\0';
        char reply[64];
        const char *out = reply;
        size_t len;
        if (strcmp(req, "SUB_PORT") == 0) snprintf(reply, sizeof reply, "%d", f->sub_port);
        else if (strcmp(req, "t") == 0) snprintf(reply, sizeof reply, "%.9f", (double)fake_capture_pupil_now_ns(f) * 1e-9);
        else if (strcmp(req, "v") == 0) snprintf(reply, sizeof reply, "3.5.fake");
        else snprintf(reply, sizeof reply, "Unknown command.");
        len = strlen(reply);
        if (strcmp(req, "t") == 0) {
            if (f->t_delay_ms > 0) sleep_ns(f->t_delay_ms * INT64_C(1000000));
            if (f->t_reply) out = f->t_reply, len = f->t_reply_len;
            atomic_fetch_add(&f->t_requests, 1);
        }
        zmq_send(f->rep, out, len, 0);
    }
    return NULL;
}

static void *pub_main(void *arg)
{
    fake_capture *f = arg;
    /* XPUB: wait for the "gaze." subscription, then play */
    while (!atomic_load(&f->stop) && !atomic_load(&f->subscribed)) {
        zmq_pollitem_t it = {f->pub, 0, ZMQ_POLLIN, 0};
        if (zmq_poll(&it, 1, 10) <= 0) continue;
        char sub[64];
        int n = zmq_recv(f->pub, sub, sizeof sub, 0);
        if (n >= 6 && sub[0] == 1 && memcmp(sub + 1, "gaze.", 5) == 0) atomic_store(&f->subscribed, 1);
    }
    for (size_t i = 0; i < f->script_len && !atomic_load(&f->stop); i++) {
        const fake_msg *m = &f->script[i];
        sleep_ns(m->due_pupil_ns - fake_capture_pupil_now_ns(f));
        zmq_send(f->pub, m->topic, strlen(m->topic), m->single_frame ? 0 : ZMQ_SNDMORE);
        if (!m->single_frame) zmq_send(f->pub, m->payload, m->len, 0);
        atomic_fetch_add(&f->published, 1);
    }
    return NULL;
}

int fake_capture_start(fake_capture *f, int remote_port, int64_t pupil_now_ns)
{
    memset(f, 0, sizeof *f);
    f->offset_ns = pupil_now_ns - fv_time_monotonic_ns();
    f->ctx = zmq_ctx_new();
    f->rep = zmq_socket(f->ctx, ZMQ_REP);
    f->pub = zmq_socket(f->ctx, ZMQ_XPUB);
    int zero = 0, big = 100000;
    zmq_setsockopt(f->rep, ZMQ_LINGER, &zero, sizeof zero);
    zmq_setsockopt(f->pub, ZMQ_LINGER, &zero, sizeof zero);
    zmq_setsockopt(f->pub, ZMQ_SNDHWM, &big, sizeof big);
    char ep[64];
    snprintf(ep, sizeof ep, remote_port ? "tcp://127.0.0.1:%d" : "tcp://127.0.0.1:*", remote_port);
    if (zmq_bind(f->rep, ep) != 0 || zmq_bind(f->pub, "tcp://127.0.0.1:*") != 0) return -1;
    f->remote_port = bound_port(f->rep);
    f->sub_port = bound_port(f->pub);
    if (pthread_create(&f->rep_thread, NULL, rep_main, f) != 0) return -1;
    f->rep_running = true;
    return 0;
}

int fake_capture_play(fake_capture *f, const fake_msg *script, size_t n)
{
    f->script = script;
    f->script_len = n;
    if (pthread_create(&f->pub_thread, NULL, pub_main, f) != 0) return -1;
    f->pub_running = true;
    return 0;
}

int fake_capture_wait_played(fake_capture *f, int timeout_ms)
{
    for (int i = 0; i < timeout_ms; i++) {
        if ((size_t)atomic_load(&f->published) >= f->script_len) return 1;
        sleep_ns(1000000);
    }
    return 0;
}

void fake_capture_stop(fake_capture *f)
{
    atomic_store(&f->stop, true);
    if (f->pub_running) pthread_join(f->pub_thread, NULL);
    if (f->rep_running) pthread_join(f->rep_thread, NULL);
    f->pub_running = f->rep_running = false;
    if (f->rep) zmq_close(f->rep);
    if (f->pub) zmq_close(f->pub);
    if (f->ctx) zmq_ctx_term(f->ctx);
    f->rep = f->pub = f->ctx = NULL;
}
