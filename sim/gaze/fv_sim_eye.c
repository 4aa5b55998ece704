/* @brief The simulated eye (see fv_sim_eye.h). Motion is a chain of analytic segments (linear drift or pursuit,
 * minimum-jerk saccades), generated ahead of time from its own random stream, so the truth at any instant does not
 * depend on how it was queried. Blinks, the pupil and the tracker noise use separate streams. */
#include "fv_sim_eye.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_log.h"
#include "fv_math.h"

#define SEG_CAP 1024
#define EVENT_CAP 8192
#define BLINK_CAP 256
#define YAW_LIMIT_DEG 25.0
#define PITCH_LIMIT_DEG 18.0
#define NS_PER_S 1.0e9

/* ---- random numbers: xoshiro256** seeded by splitmix64 (Blackman & Vigna) ---- */

typedef struct rng {
    uint64_t s[4];
} rng;

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

static void rng_seed(rng *r, uint64_t seed, uint64_t stream)
{
    uint64_t x = seed ^ (stream * UINT64_C(0xD1B54A32D192ED03));
    for (int i = 0; i < 4; i++) r->s[i] = splitmix64(&x);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static uint64_t rng_u64(rng *r)
{
    uint64_t *s = r->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

/* uniform in [0, 1) */
static double rng_uniform(rng *r) { return (double)(rng_u64(r) >> 11) * (1.0 / 9007199254740992.0); }
static double rng_range(rng *r, double lo, double hi) { return lo + (hi - lo) * rng_uniform(r); }
static double rng_normal(rng *r)
{
    double u1 = rng_uniform(r), u2 = rng_uniform(r);
    if (u1 < 1e-300) u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * FV_PI * u2);
}
static double rng_exp(rng *r, double mean) { return -mean * log(1.0 - rng_uniform(r)); }
static double clampd(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* ---- state ---- */

typedef enum seg_kind { SEG_LINEAR, SEG_MINJERK } seg_kind;

typedef struct segment {
    int64_t t0, t1;
    seg_kind kind;
    fv_sim_label label;
    double y0, p0, y1, p1;   /* yaw/pitch at start and end, deg */
    double d0, d1;           /* depth at start and end, m */
} segment;

struct fv_sim_eye {
    fv_sim_eye_desc d;
    rng motion_rng, blink_rng, sample_rng, pupil_rng;
    /* motion */
    segment seg[SEG_CAP];
    size_t seg_first, seg_count; /* absolute index of the oldest kept segment, how many are kept */
    int64_t t_gen;               /* motion generated up to here */
    double yaw, pitch, depth;    /* state at t_gen */
    bool after_pursuit;
    /* blinks */
    int64_t blink_t0[BLINK_CAP], blink_t1[BLINK_CAP];
    size_t blink_first, blink_count;
    int64_t blink_gen;           /* the next blink starts after this */
    /* events */
    fv_sim_event ev[EVENT_CAP];
    size_t ev_count;             /* total ever appended */
    /* samples */
    uint64_t k;                  /* next sample index */
    int64_t last_capture, last_arrival;
    double bias[2][2];           /* per-eye accuracy offset, deg */
    /* pupil */
    double pupil, pupil_target;
    int64_t pupil_t, light_next;
    double hippus_phase[2];
};

const char *fv_sim_label_str(fv_sim_label l)
{
    switch (l) {
    case FV_SIM_NONE: return "none";
    case FV_SIM_FIXATION: return "fixation";
    case FV_SIM_SACCADE: return "saccade";
    case FV_SIM_PURSUIT: return "pursuit";
    case FV_SIM_MICROSACCADE: return "microsaccade";
    case FV_SIM_BLINK: return "blink";
    }
    return "unknown";
}

void fv_sim_eye_desc_defaults(fv_sim_eye_desc *d)
{
    memset(d, 0, sizeof *d);
    d->seed = 1;
    d->rate_hz = 120.0;
    d->jitter_us = 50.0;
    d->latency_ms = 4.0;
    d->transport_jitter_ms = 0.5;
    d->dropout = 0.002;
    d->eye_loss = 0.003;
    d->precision_deg = 0.15;
    d->accuracy_deg = 0.5;
    d->blink_per_min = 15.0;
    d->pursuit_prob = 0.15;
    d->microsaccades = true;
    d->skew_ppm = 20.0;
    d->device_offset_s = 1000.0;
    d->ipd_mm = 63.0;
    d->vmax_deg_s = 600.0;
    d->c_deg = 9.0;
    d->main_seq_spread = 0.08;
}

static bool in_range(const char *name, double v, double lo, double hi)
{
    if (isfinite(v) && v >= lo && v <= hi) return true;
    FV_ERROR("sim", "simulated eye: %s = %g is outside [%g, %g]", name, v, lo, hi);
    return false;
}

static bool validate(const fv_sim_eye_desc *d)
{
    bool ok = true;
    ok &= in_range("rate_hz", d->rate_hz, 30.0, 1200.0);
    if (ok) ok &= in_range("jitter_us", d->jitter_us, 0.0, 1.0e6 / d->rate_hz * 0.25); /* its range needs a valid rate */
    ok &= in_range("latency_ms", d->latency_ms, 0.0, 1000.0);
    ok &= in_range("transport_jitter_ms", d->transport_jitter_ms, 0.0, 100.0);
    ok &= in_range("dropout", d->dropout, 0.0, 0.9);
    ok &= in_range("eye_loss", d->eye_loss, 0.0, 1.0);
    ok &= in_range("precision_deg", d->precision_deg, 0.0, 10.0);
    ok &= in_range("accuracy_deg", d->accuracy_deg, 0.0, 10.0);
    ok &= in_range("blink_per_min", d->blink_per_min, 0.0, 60.0);
    ok &= in_range("pursuit_prob", d->pursuit_prob, 0.0, 1.0);
    ok &= in_range("skew_ppm", d->skew_ppm, -1000.0, 1000.0);
    ok &= in_range("device_offset_s", d->device_offset_s, -1.0e9, 1.0e9);
    ok &= in_range("ipd_mm", d->ipd_mm, 40.0, 90.0);
    ok &= in_range("vmax_deg_s", d->vmax_deg_s, 100.0, 2000.0);
    ok &= in_range("c_deg", d->c_deg, 1.0, 50.0);
    ok &= in_range("main_seq_spread", d->main_seq_spread, 0.0, 0.5);
    return ok;
}

/* ---- events ---- */

static void add_event(fv_sim_eye *e, fv_sim_label l, int64_t t0, int64_t t1, double amp, double peak)
{
    fv_sim_event *ev = &e->ev[e->ev_count % EVENT_CAP];
    ev->label = l;
    ev->t_start_ns = t0;
    ev->t_end_ns = t1;
    ev->amplitude_deg = amp;
    ev->peak_deg_s = peak;
    e->ev_count++;
}

size_t fv_sim_eye_event_count(const fv_sim_eye *eye) { return eye->ev_count; }

bool fv_sim_eye_event_get(const fv_sim_eye *eye, size_t index, fv_sim_event *out)
{
    if (index >= eye->ev_count || eye->ev_count - index > EVENT_CAP) return false;
    *out = eye->ev[index % EVENT_CAP];
    return true;
}

/* ---- motion generation ---- */

static void add_segment(fv_sim_eye *e, int64_t dur_ns, seg_kind kind, fv_sim_label label, double y1, double p1,
                        double d1)
{
    if (dur_ns < 1) dur_ns = 1;
    if (e->seg_count == SEG_CAP) {
        e->seg_first++;
        e->seg_count--;
    }
    segment *s = &e->seg[(e->seg_first + e->seg_count) % SEG_CAP];
    s->t0 = e->t_gen;
    s->t1 = e->t_gen + dur_ns;
    s->kind = kind;
    s->label = label;
    s->y0 = e->yaw;
    s->p0 = e->pitch;
    s->d0 = e->depth;
    s->y1 = y1;
    s->p1 = p1;
    s->d1 = d1;
    e->seg_count++;
    e->t_gen = s->t1;
    e->yaw = y1;
    e->pitch = p1;
    e->depth = d1;
}

/* Main sequence with per-saccade spread; minimum-jerk profile: D = 1.875 A / Vp. */
static void saccade_kinematics(fv_sim_eye *e, double amp, double *out_peak, double *out_dur_s)
{
    double vp = e->d.vmax_deg_s * (1.0 - exp(-amp / e->d.c_deg));
    vp *= exp(e->d.main_seq_spread * rng_normal(&e->motion_rng));
    if (vp < 1e-3) vp = 1e-3;
    *out_peak = vp;
    *out_dur_s = 1.875 * amp / vp;
}

static void gen_saccade_to(fv_sim_eye *e, double y1, double p1, double d1, fv_sim_label label)
{
    double dy = (y1 - e->yaw) * cos(fv_deg_to_rad(0.5 * (p1 + e->pitch))), dp = p1 - e->pitch;
    double amp = sqrt(dy * dy + dp * dp);
    double peak, dur;
    saccade_kinematics(e, amp, &peak, &dur);
    int64_t t0 = e->t_gen;
    add_segment(e, (int64_t)(dur * NS_PER_S), SEG_MINJERK, label, y1, p1, d1);
    add_event(e, label, t0, e->t_gen, amp, peak);
}

static void gen_fixation(fv_sim_eye *e)
{
    /* Fixation durations: log-normal, median 250 ms, clipped to 100..1500 ms (free viewing; e.g. Henderson 2003) */
    double dur = clampd(0.25 * exp(0.4 * rng_normal(&e->motion_rng)), 0.10, 1.5);
    int64_t t_start = e->t_gen, t_end = t_start + (int64_t)(dur * NS_PER_S);
    double ay = e->yaw, ap = e->pitch; /* the fixated target: drift and microsaccades stay around it */
    while (e->t_gen < t_end) {
        int64_t left = t_end - e->t_gen;
        if (!e->d.microsaccades) {
            add_segment(e, left, SEG_LINEAR, FV_SIM_FIXATION, e->yaw, e->pitch, e->depth);
            break;
        }
        /* drift: slow random velocity (0.1..0.5 deg/s) until the next microsaccade (~1.2/s) */
        int64_t piece = (int64_t)(rng_exp(&e->motion_rng, 1.0 / 1.2) * NS_PER_S);
        if (piece > left) piece = left;
        double speed = rng_range(&e->motion_rng, 0.1, 0.5), th = rng_range(&e->motion_rng, 0.0, 2.0 * FV_PI);
        double ps = (double)piece / NS_PER_S;
        add_segment(e, piece, SEG_LINEAR, FV_SIM_FIXATION, e->yaw + speed * ps * cos(th), e->pitch + speed * ps * sin(th),
                    e->depth);
        if (e->t_gen >= t_end) break;
        /* microsaccade: 0.05..0.8 deg, aimed back toward the target with some scatter */
        double amp = clampd(0.25 * exp(0.5 * rng_normal(&e->motion_rng)), 0.05, 0.8);
        double back = atan2(ap - e->pitch, ay - e->yaw) + 0.8 * rng_normal(&e->motion_rng);
        double peak, sdur;
        saccade_kinematics(e, amp, &peak, &sdur);
        if (e->t_gen + (int64_t)(sdur * NS_PER_S) > t_end) break;
        int64_t t0 = e->t_gen;
        add_segment(e, (int64_t)(sdur * NS_PER_S), SEG_MINJERK, FV_SIM_MICROSACCADE, e->yaw + amp * cos(back),
                    e->pitch + amp * sin(back), e->depth);
        add_event(e, FV_SIM_MICROSACCADE, t0, e->t_gen, amp, peak);
    }
    if (e->t_gen < t_end) add_segment(e, t_end - e->t_gen, SEG_LINEAR, FV_SIM_FIXATION, e->yaw, e->pitch, e->depth);
    add_event(e, FV_SIM_FIXATION, t_start, e->t_gen, 0.0, 0.0);
}

static void gen_shift(fv_sim_eye *e)
{
    /* Saccade amplitudes: log-normal, median 6 deg, 2..30 deg; targets kept within the central field. */
    double amp = clampd(6.0 * exp(0.6 * rng_normal(&e->motion_rng)), 2.0, 30.0);
    double y1 = e->yaw, p1 = e->pitch;
    for (int tries = 0; tries < 16; tries++) {
        double th = rng_range(&e->motion_rng, 0.0, 2.0 * FV_PI);
        /* horizontal saccades are more common: squash the vertical part */
        double cy = cos(th), sy = 0.7 * sin(th), n = sqrt(cy * cy + sy * sy);
        y1 = e->yaw + amp * cy / n;
        p1 = e->pitch + amp * sy / n;
        if (fabs(y1) <= YAW_LIMIT_DEG && fabs(p1) <= PITCH_LIMIT_DEG) break;
        if (tries == 15) { /* aim at the centre instead */
            double th0 = atan2(-e->pitch, -e->yaw);
            y1 = clampd(e->yaw + amp * cos(th0), -YAW_LIMIT_DEG, YAW_LIMIT_DEG);
            p1 = clampd(e->pitch + amp * sin(th0), -PITCH_LIMIT_DEG, PITCH_LIMIT_DEG);
        }
    }
    /* the new target's depth: log-uniform 0.4..4 m */
    double d1 = 0.4 * pow(10.0, rng_uniform(&e->motion_rng));
    gen_saccade_to(e, y1, p1, d1, FV_SIM_SACCADE);
}

static void gen_pursuit(fv_sim_eye *e)
{
    /* A target moving at 6..25 deg/s for 0.4..1.5 s, clipped to the field. */
    double speed = rng_range(&e->motion_rng, 6.0, 25.0);
    double th = rng_range(&e->motion_rng, 0.0, 2.0 * FV_PI);
    double dur = rng_range(&e->motion_rng, 0.4, 1.5);
    double vy = speed * cos(th), vp = 0.7 * speed * sin(th);
    double tmax = dur;
    if (vy > 0) tmax = fmin(tmax, (YAW_LIMIT_DEG - e->yaw) / vy);
    if (vy < 0) tmax = fmin(tmax, (-YAW_LIMIT_DEG - e->yaw) / vy);
    if (vp > 0) tmax = fmin(tmax, (PITCH_LIMIT_DEG - e->pitch) / vp);
    if (vp < 0) tmax = fmin(tmax, (-PITCH_LIMIT_DEG - e->pitch) / vp);
    if (tmax < 0.2) return; /* no room: skip */
    int64_t t0 = e->t_gen;
    add_segment(e, (int64_t)(tmax * NS_PER_S), SEG_LINEAR, FV_SIM_PURSUIT, e->yaw + vy * tmax, e->pitch + vp * tmax,
                e->depth);
    add_event(e, FV_SIM_PURSUIT, t0, e->t_gen, sqrt(vy * vy + vp * vp), 0.0);
}

static void gen_block(fv_sim_eye *e)
{
    gen_fixation(e);
    gen_shift(e);
    if (rng_uniform(&e->motion_rng) < e->d.pursuit_prob) gen_pursuit(e);
}

static void gen_blinks_until(fv_sim_eye *e, int64_t t)
{
    if (e->d.blink_per_min <= 0.0) return;
    while (e->blink_gen <= t) {
        /* inter-blink gaps: exponential (at least 0.5 s) with the mean that gives blink_per_min including the
         * blinks' own ~0.19 s */
        double gap = fmax(0.5, rng_exp(&e->blink_rng, fmax(0.1, 60.0 / e->d.blink_per_min - 0.19)));
        /* blink durations: log-normal, median 180 ms, 100..400 ms */
        double dur = clampd(0.18 * exp(0.3 * rng_normal(&e->blink_rng)), 0.10, 0.40);
        int64_t t0 = e->blink_gen + (int64_t)(gap * NS_PER_S);
        int64_t t1 = t0 + (int64_t)(dur * NS_PER_S);
        if (e->blink_count == BLINK_CAP) {
            e->blink_first++;
            e->blink_count--;
        }
        size_t k = (e->blink_first + e->blink_count) % BLINK_CAP;
        e->blink_t0[k] = t0;
        e->blink_t1[k] = t1;
        e->blink_count++;
        e->blink_gen = t1;
        add_event(e, FV_SIM_BLINK, t0, t1, 0.0, 0.0);
    }
}

void fv_sim_eye_generate_until(fv_sim_eye *eye, int64_t t_ns)
{
    while (eye->t_gen <= t_ns) gen_block(eye);
    gen_blinks_until(eye, t_ns);
}

static bool in_blink(const fv_sim_eye *e, int64_t t)
{
    for (size_t i = 0; i < e->blink_count; i++) {
        size_t k = (e->blink_first + i) % BLINK_CAP;
        if (t >= e->blink_t0[k] && t < e->blink_t1[k]) return true;
    }
    return false;
}

/* ---- truth ---- */

static fv_vec3 angles_dir(double yaw, double pitch)
{
    double cy = cos(fv_deg_to_rad(yaw)), sy = sin(fv_deg_to_rad(yaw));
    double cp = cos(fv_deg_to_rad(pitch)), sp = sin(fv_deg_to_rad(pitch));
    return fv_v3((float)(sy * cp), (float)sp, (float)(-cy * cp));
}

static double minjerk(double u)
{
    if (u <= 0.0) return 0.0;
    if (u >= 1.0) return 1.0;
    return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

static void fill_eyes(const fv_sim_eye *e, fv_sim_truth *t)
{
    t->dir_cyc = angles_dir(t->yaw_deg, t->pitch_deg);
    fv_vec3 target = fv_v3_scale(t->dir_cyc, (float)(t->depth_m * 1000.0));
    for (int k = 0; k < 2; k++) {
        fv_vec3 origin = fv_v3((float)((k == 0 ? -0.5 : 0.5) * e->d.ipd_mm), 0.0f, 0.0f);
        t->dir_eye[k] = fv_v3_normalize_or(fv_v3_sub(target, origin), t->dir_cyc);
    }
}

bool fv_sim_eye_truth_at(fv_sim_eye *eye, int64_t t_ns, fv_sim_truth *out)
{
    if (t_ns < 0) return false;
    fv_sim_eye_generate_until(eye, t_ns);
    if (eye->seg_count == 0) return false;
    const segment *oldest = &eye->seg[eye->seg_first % SEG_CAP];
    if (t_ns < oldest->t0) return false;
    /* binary search over the kept segments (contiguous in time) */
    size_t lo = 0, hi = eye->seg_count - 1;
    while (lo < hi) {
        size_t mid = (lo + hi + 1) / 2;
        if (eye->seg[(eye->seg_first + mid) % SEG_CAP].t0 <= t_ns) lo = mid;
        else hi = mid - 1;
    }
    const segment *s = &eye->seg[(eye->seg_first + lo) % SEG_CAP];
    double u = (double)(t_ns - s->t0) / (double)(s->t1 - s->t0);
    u = clampd(u, 0.0, 1.0);
    double f = s->kind == SEG_MINJERK ? minjerk(u) : u;
    memset(out, 0, sizeof *out);
    out->t_ns = t_ns;
    out->yaw_deg = s->y0 + (s->y1 - s->y0) * f;
    out->pitch_deg = s->p0 + (s->p1 - s->p0) * f;
    out->depth_m = s->d0 + (s->d1 - s->d0) * f;
    out->label = s->label;
    out->blink = in_blink(eye, t_ns);
    out->pupil_mm = NAN;
    fill_eyes(eye, out);
    return true;
}

/* ---- pupil ---- */

/* Moon & Spencer (1944): D = 4.9 - 3 tanh(0.4 (log10 L + 1)) mm, L in cd/m^2: about 2 mm (bright) to 8 mm (dark). */
static double pupil_for_luminance(double log10_l) { return 4.9 - 3.0 * tanh(0.4 * (log10_l + 1.0)); }

static double pupil_at(fv_sim_eye *e, int64_t t)
{
    while (t >= e->light_next) {
        /* the scene's luminance changes every ~8 s (exponential), log10 L uniform in [-4, 3] (night to daylight) */
        e->pupil_target = pupil_for_luminance(rng_range(&e->pupil_rng, -4.0, 3.0));
        e->light_next += (int64_t)(fmax(1.0, rng_exp(&e->pupil_rng, 8.0)) * NS_PER_S);
    }
    double dt = (double)(t - e->pupil_t) / NS_PER_S;
    if (dt > 0) {
        /* first-order response: constriction (tau 0.3 s) faster than dilation (tau 1.2 s) */
        double tau = e->pupil_target < e->pupil ? 0.3 : 1.2;
        e->pupil += (e->pupil_target - e->pupil) * (1.0 - exp(-dt / tau));
        e->pupil_t = t;
    }
    /* hippus: slow irregular oscillation, ~0.1-0.3 mm, below 1 Hz */
    double ts = (double)t / NS_PER_S;
    double h = 0.12 * sin(2.0 * FV_PI * 0.23 * ts + e->hippus_phase[0]) +
               0.07 * sin(2.0 * FV_PI * 0.61 * ts + e->hippus_phase[1]);
    return clampd(e->pupil + h, 2.0, 8.0);
}

/* ---- lifetime ---- */

fv_result fv_sim_eye_create(const fv_sim_eye_desc *desc, fv_sim_eye **out)
{
    if (!desc || !out) return FV_ERR_INVALID_ARG;
    *out = NULL;
    if (!validate(desc)) return FV_ERR_RANGE;
    fv_sim_eye *e = calloc(1, sizeof *e);
    if (!e) return FV_ERR_NO_MEMORY;
    e->d = *desc;
    rng_seed(&e->motion_rng, desc->seed, 1);
    rng_seed(&e->blink_rng, desc->seed, 2);
    rng_seed(&e->sample_rng, desc->seed, 3);
    rng_seed(&e->pupil_rng, desc->seed, 4);
    e->yaw = rng_range(&e->motion_rng, -10.0, 10.0);
    e->pitch = rng_range(&e->motion_rng, -5.0, 5.0);
    e->depth = 1.0;
    e->blink_gen = 0;
    for (int k = 0; k < 2; k++) {
        double th = rng_range(&e->sample_rng, 0.0, 2.0 * FV_PI);
        e->bias[k][0] = desc->accuracy_deg * cos(th);
        e->bias[k][1] = desc->accuracy_deg * sin(th);
    }
    e->pupil_target = pupil_for_luminance(rng_range(&e->pupil_rng, -4.0, 3.0));
    e->pupil = e->pupil_target;
    e->light_next = (int64_t)(fmax(1.0, rng_exp(&e->pupil_rng, 8.0)) * NS_PER_S);
    e->hippus_phase[0] = rng_range(&e->pupil_rng, 0.0, 2.0 * FV_PI);
    e->hippus_phase[1] = rng_range(&e->pupil_rng, 0.0, 2.0 * FV_PI);
    e->last_capture = -1;
    *out = e;
    return FV_OK;
}

void fv_sim_eye_destroy(fv_sim_eye **eye)
{
    if (!eye || !*eye) return;
    free(*eye);
    *eye = NULL;
}

const fv_sim_eye_desc *fv_sim_eye_get_desc(const fv_sim_eye *eye) { return &eye->d; }

/* ---- samples ---- */

static fv_eye_sample noisy_eye(fv_sim_eye *e, int k, const fv_sim_truth *t, double pupil)
{
    fv_eye_sample s;
    double yaw = fv_rad_to_deg(atan2(t->dir_eye[k].x, -t->dir_eye[k].z));
    double pitch = fv_rad_to_deg(asin(clampd(t->dir_eye[k].y, -1.0, 1.0)));
    yaw += e->bias[k][0] + e->d.precision_deg * rng_normal(&e->sample_rng);
    pitch += e->bias[k][1] + e->d.precision_deg * rng_normal(&e->sample_rng);
    s.origin_mm = fv_v3((float)((k == 0 ? -0.5 : 0.5) * e->d.ipd_mm), 0.0f, 0.0f);
    s.direction = angles_dir(yaw, pitch);
    s.pupil_mm = (float)clampd(pupil + 0.05 * rng_normal(&e->sample_rng), 0.5, 12.0);
    s.openness = 1.0f;
    s.flags = FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID | FV_EYE_OPENNESS_VALID;
    return s;
}

fv_result fv_sim_eye_next(fv_sim_eye *e, fv_gaze_sample *out, fv_sim_truth *out_truth)
{
    if (!e || !out || !out_truth) return FV_ERR_INVALID_ARG;
    double period_ns = NS_PER_S / e->d.rate_hz;
    for (;;) {
        uint64_t k = e->k++;
        int64_t t = (int64_t)llround((double)k * period_ns + e->d.jitter_us * 1e3 * rng_normal(&e->sample_rng));
        if (t <= e->last_capture) t = e->last_capture + 1;
        if (t < 0) t = 0;
        e->last_capture = t;
        bool dropped = rng_uniform(&e->sample_rng) < e->d.dropout;
        double loss_draw = rng_uniform(&e->sample_rng);
        double transport = e->d.transport_jitter_ms > 0 ? rng_exp(&e->sample_rng, e->d.transport_jitter_ms) : 0.0;
        double pupil = pupil_at(e, t);
        if (dropped) continue;
        fv_sim_truth tr;
        if (!fv_sim_eye_truth_at(e, t, &tr)) return FV_ERR_STATE;
        tr.pupil_mm = pupil;
        double dev = e->d.device_offset_s * NS_PER_S + (double)t * (1.0 + e->d.skew_ppm * 1e-6);
        int64_t arrival = t + (int64_t)llround((e->d.latency_ms + transport) * 1e6);
        if (arrival < e->last_arrival) arrival = e->last_arrival; /* the transport keeps order */
        e->last_arrival = arrival;
        fv_gaze_sample_init_invalid(out, (int64_t)llround(dev), arrival);
        out->flags = FV_GAZE_HOST_TIME_VALID;
        out->seq = k;
        if (tr.blink) {
            for (int i = 0; i < 2; i++) {
                out->eye[i].flags = FV_EYE_BLINK | FV_EYE_OPENNESS_VALID;
                out->eye[i].openness = 0.0f;
            }
            out->combined.flags = FV_EYE_BLINK;
            out->confidence = 0.0f;
        } else {
            int lost = loss_draw < e->d.eye_loss ? (loss_draw < 0.5 * e->d.eye_loss ? 0 : 1) : -1;
            for (int i = 0; i < 2; i++)
                if (i != lost) out->eye[i] = noisy_eye(e, i, &tr, pupil);
            if (lost < 0) {
                fv_vec3 sum = fv_v3_add(out->eye[0].direction, out->eye[1].direction);
                out->combined.direction = fv_v3_normalize_or(sum, tr.dir_cyc);
                out->combined.origin_mm = fv_v3(0.0f, 0.0f, 0.0f);
                out->combined.pupil_mm = 0.5f * (out->eye[0].pupil_mm + out->eye[1].pupil_mm);
                out->combined.openness = 1.0f;
                out->combined.flags = FV_EYE_ORIGIN_VALID | FV_EYE_DIRECTION_VALID | FV_EYE_PUPIL_VALID |
                                      FV_EYE_OPENNESS_VALID;
            }
            out->confidence = lost < 0 ? 0.95f : 0.6f;
        }
        *out_truth = tr;
        return FV_OK;
    }
}
