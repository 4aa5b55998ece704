/* @brief The gaze pipeline's candidate predictors (the newest sample, the filtered position, the model, the sample
 * moved by the shrunk velocity and by half of it, the blend), their online scoring per context against the raw gaze
 * that arrives later, and the choice among them with the device-level fallback (see fv_gaze_pipeline.c). */
#include "gaze_pipeline_internal.h"

#include <math.h>

/* The candidate predictions at horizon h_s (clamped) after the newest valid sample for motion state ev:
 * the newest raw sample, the filtered position, and the model (fixation and pursuit: the filtered position moved
 * toward the line through the newest 50 ms, extrapolated by the share of its velocity that stands out of the noise,
 * g = 1 - (k/z)^2 for a velocity z standard errors from zero (James-Stein shrinkage; 0 below k): a fixation's drift
 * is within the noise, g = 0, the filtered position; a pursuit's velocity is not, g -> 1, the line free of the
 * filter's lag. Saccade: the main-sequence landing once the fit is confident, else the newest position).
 * *extra_unc: what the model adds to the uncertainty beyond the fixation growth. */
/* The blend: the newest sample moved by the share lambda of the model's step from it that has paid off in this
 * context (least squares on the scored samples: lambda = E[(truth - sample).(model - sample)] / E[|model -
 * sample|^2], clamped to [0, 1]) -- shrinkage of the predicted displacement toward zero by its measured benefit. */
static void blend(const fv_gaze_pipeline *p, fv_gaze_event ev, double cand[CANDS][2])
{
    int cx = fv_gaze_context(p, ev), st = cx / SPEED_BINS;
    double num = 0.0, den = 0.0;
    if (p->scored[cx] >= SCORE_MIN) num = p->lam_num[cx], den = p->lam_den[cx];
    else if (p->scored_state[st] >= SCORE_MIN) num = p->lam_num_state[st], den = p->lam_den_state[st];
    double lam = den > 1e-12 ? fmax(0.0, fmin(1.0, num / den)) : 0.0;
    if (!isfinite(lam) || p->tun.blend < 0.0) lam = 0.0; /* without the blend: the newest sample, never chosen */
    for (int a = 0; a < 2; a++)
        cand[CAND_BLEND][a] = cand[CAND_SAMPLE][a] + lam * (cand[CAND_MODEL][a] - cand[CAND_SAMPLE][a]);
}

void fv_gaze_candidates(const fv_gaze_pipeline *p, fv_gaze_event ev, double h_s, double cand[CANDS][2],
                       double *extra_unc)
{
    const double *raw = p->h_p[hist_index(p, 0)];
    const channel *cc = &p->ch[CH_COMBINED];
    double hpos = fmax(0.0, h_s);
    for (int a = 0; a < 2; a++) {
        cand[CAND_SAMPLE][a] = p->h_count > 0 ? raw[a] : cc->pos[a];
        cand[CAND_FILTERED][a] = cc->pos[a];
        cand[CAND_MODEL][a] = cc->pos[a];
        cand[CAND_SAMPLE_VEL][a] = cand[CAND_SAMPLE][a];
        cand[CAND_SAMPLE_HALF][a] = cand[CAND_SAMPLE][a];
        cand[CAND_BLEND][a] = cand[CAND_SAMPLE][a];
    }
    if (ev == FV_GAZE_EVENT_SACCADE) {
        double remaining = 0.0;
        int64_t target = fv_i64_add_sat(p->last_valid_ns, (int64_t)(h_s * 1e9));
        if (!p->fit_confident || !fv_gaze_predict_saccade(p, target, cand[CAND_MODEL], &remaining)) {
            /* no trustworthy landing yet: the newest position (the saccade's extent is unknown) */
            cand[CAND_MODEL][0] = cc->pos[0];
            cand[CAND_MODEL][1] = cc->pos[1];
            remaining = ang_norm(p->v_short, cc->pos[1]) * hpos;
        }
        *extra_unc = 0.5 + 0.25 * remaining;
        /* the velocity slot: the landing fit even before it is confident (from its first two samples, the
         * amplitude prior decides); the scorer keeps it only where it pays */
        double r2;
        if (p->fit_ok && !fv_gaze_predict_saccade(p, target, cand[CAND_SAMPLE_VEL], &r2)) {
            cand[CAND_SAMPLE_VEL][0] = cand[CAND_SAMPLE][0];
            cand[CAND_SAMPLE_VEL][1] = cand[CAND_SAMPLE][1];
        }
        /* inside a saccade the half-velocity slot holds the newest sample moved by the 20 ms velocity (a head
         * movement read as a saccade continues; the velocity slot stays the sample) */
        double lim = p->desc.max_eccentricity_deg;
        for (int a = 0; a < 2; a++)
            cand[CAND_SAMPLE_HALF][a] = fmax(-lim, fmin(lim, cand[CAND_SAMPLE_HALF][a] + p->v_short[a] * hpos));
        blend(p, ev, cand);
        return;
    }
    double z = p->v_mid_sig, k = SHRINK_SDS, g = z > k ? 1.0 - (k / z) * (k / z) : 0.0;
    for (int a = 0; a < 2; a++) {
        cand[CAND_MODEL][a] += g * (p->mid_pos[a] + p->v_mid[a] * h_s - cc->pos[a]);
        cand[CAND_SAMPLE_VEL][a] += g * p->v_mid[a] * h_s;
        cand[CAND_SAMPLE_HALF][a] += 0.5 * g * p->v_mid[a] * h_s;
    }
    *extra_unc = 0.25 * g * ang_norm(p->v_mid, cc->pos[1]) * hpos;
    blend(p, ev, cand);
}

/* The scoring context of state ev now: the state and a bin of the speed over the newest 50 ms (< 5, < 20, < 60,
 * >= 60 deg/s): the best candidate of a slow pursuit is not that of a fast one. Inside a saccade that speed is the
 * one before it (the 50 ms velocity is not updated in flight). A saccade that began from a fixation or a slow
 * pursuit (< 20 deg/s) is binned by how many of its samples have been seen instead (1: bin 0, 2: bin 4, 3 or more:
 * bin 5): what a candidate is worth depends on how much of the saccade the landing fit has had -- from one
 * displacement its amplitude is uncertain by a factor of several, from three it is not -- and a context mixing
 * the two takes the first samples' choice from the later ones' scores. One that began from fast motion (a head
 * movement on a head-worn tracker, a catch-up saccade in a fast pursuit) keeps its speed bin. */
int fv_gaze_context(const fv_gaze_pipeline *p, fv_gaze_event ev)
{
    int st = (int)ev >= 0 && (int)ev < STATES ? (int)ev : 0;
    double v = ang_norm(p->v_mid, p->h_count > 0 ? p->h_p[hist_index(p, 0)][1] : 0.0);
    double k = p->tun.speed_bin_scale;
    int bin = !(v >= 5.0 * k) ? 0 : v < 20.0 * k ? 1 : v < 60.0 * k ? 2 : 3;
    if (ev == FV_GAZE_EVENT_SACCADE && p->state == FV_GAZE_EVENT_SACCADE && !(v >= p->tun.slow_saccade_deg_s)) {
        int seen = 0;
        while (seen < p->h_count && seen < 3 && p->h_t[hist_index(p, seen)] >= p->sacc_start_ns) seen++;
        bin = seen <= 1 ? 0 : 2 + seen;
    }
    return st * SPEED_BINS + bin;
}

/* Prediction earns its place: every valid sample leaves the candidates' predictions for SCORE_HORIZON ahead; when
 * the samples around that time arrive, each candidate's angular error against the raw gaze interpolated there
 * enters a running mean per context (motion state x speed bin; the state alone until the context has SCORE_MIN).
 * fv_gaze_choose_candidate() keeps the newest sample unless another candidate has led it by SELECT_SES standard errors in
 * this context (a tracker whose own filtering leaves nothing to gain, a noisy one where the saccade fit misleads).
 * The raw truth carries the tracker's noise, which is independent of every candidate 20 ms earlier. The mean
 * absolute error, not the mean square, ranks them: a candidate with rare large misses (a landing fit on a head
 * movement) loses less to them, and the 95th percentile followed better on the recordings. */
/* Where prediction cannot help on this device (a tracker that filters heavily itself, or one whose motion the eye
 * data do not foretell), the whole device falls back: the selection's choices are scored against the newest sample
 * too, over every context, and while their running mean is not below it (after fallback_min scores) predict()
 * returns the newest sample. The check goes on in the background, so prediction comes back when it pays again. */
int fv_gaze_choose_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev)
{
    return p->fallback ? CAND_SAMPLE : fv_gaze_select_candidate(p, ev);
}

void fv_gaze_score_candidates(fv_gaze_pipeline *p, int64_t t, const double pos[2])
{
    while (p->pend_count > 0) {
        int i = (p->pend_head - p->pend_count + PEND_SLOTS) % PEND_SLOTS;
        if (p->pend[i].t_ns > t) break;
        p->pend_count--;
        int64_t gap = fv_i64_sub_sat(t, p->prev_raw_ns);
        if (!p->have_prev_raw || p->pend[i].t_ns < p->prev_raw_ns || gap > GAP_RESET_NS) continue;
        double w = gap > 0 ? ((double)p->pend[i].t_ns - (double)p->prev_raw_ns) / (double)gap : 1.0;
        double truth[2] = {p->prev_raw[0] + w * (pos[0] - p->prev_raw[0]), p->prev_raw[1] + w * (pos[1] - p->prev_raw[1])};
        int cx = p->pend[i].context, st = cx / SPEED_BINS;
        double lr = fmax(1.0 / ((double)p->scored[cx] + 1.0), 1.0 / SCORE_MEMORY);
        double ls = fmax(1.0 / ((double)p->scored_state[st] + 1.0), 1.0 / SCORE_MEMORY);
        double e[CANDS];
        for (int c = 0; c < CANDS; c++) {
            double d[2] = {p->pend[i].c[c][0] - truth[0], p->pend[i].c[c][1] - truth[1]};
            e[c] = ang_norm(d, truth[1]);
        }
        if (!isfinite(e[CAND_SAMPLE])) continue;
        {
            const double *s0 = p->pend[i].c[CAND_SAMPLE], *m0 = p->pend[i].c[CAND_MODEL];
            double dm[2] = {m0[0] - s0[0], m0[1] - s0[1]}, dr[2] = {truth[0] - s0[0], truth[1] - s0[1]};
            double num = dm[0] * dr[0] + dm[1] * dr[1], den = dm[0] * dm[0] + dm[1] * dm[1];
            if (isfinite(num) && isfinite(den)) {
                p->lam_num[cx] += lr * (num - p->lam_num[cx]);
                p->lam_den[cx] += lr * (den - p->lam_den[cx]);
                p->lam_num_state[st] += ls * (num - p->lam_num_state[st]);
                p->lam_den_state[st] += ls * (den - p->lam_den_state[st]);
            }
        }
        for (int c = 0; c < CANDS; c++) {
            if (!isfinite(e[c])) e[c] = e[CAND_SAMPLE] + 90.0; /* never chosen */
            double dd = e[c] - e[CAND_SAMPLE];
            p->mae[cx][c] += lr * (e[c] - p->mae[cx][c]);
            p->mae_state[st][c] += ls * (e[c] - p->mae_state[st][c]);
            p->dmean[cx][c] += lr * (dd - p->dmean[cx][c]);
            p->dsq[cx][c] += lr * (dd * dd - p->dsq[cx][c]);
            p->dmean_state[st][c] += ls * (dd - p->dmean_state[st][c]);
            p->dsq_state[st][c] += ls * (dd * dd - p->dsq_state[st][c]);
        }
        if (p->scored[cx] < UINT32_MAX) p->scored[cx]++;
        if (p->scored_state[st] < UINT32_MAX) p->scored_state[st]++;
        {
            /* the mean over every scored prediction (a choice of the sample itself adds 0) */
            int ch = p->pend[i].chosen;
            double dd = ch > CAND_SAMPLE && ch < CANDS ? e[ch] - e[CAND_SAMPLE] : 0.0;
            double lg = fmax(1.0 / ((double)p->dev_scored + 1.0), 1.0 / p->tun.fallback_memory);
            p->dev_dmean += lg * (dd - p->dev_dmean);
            p->dev_scored++;
            bool was = p->fallback;
            p->fallback = p->tun.fallback > 0.0 &&
                          ((double)p->dev_scored < p->tun.fallback_min || !(p->dev_dmean < 0.0));
            if (p->fallback != was) p->stats.fallback_switches++;
        }
    }
    p->have_prev_raw = true;
    p->prev_raw_ns = t;
    p->prev_raw[0] = pos[0];
    p->prev_raw[1] = pos[1];
    if (p->state != FV_GAZE_EVENT_FIXATION && p->state != FV_GAZE_EVENT_PURSUIT && p->state != FV_GAZE_EVENT_SACCADE)
        return;
    int i = p->pend_head;
    if (p->pend_count == PEND_SLOTS) p->pend_count--; /* the oldest gives way */
    p->pend_head = (p->pend_head + 1) % PEND_SLOTS;
    p->pend_count++;
    p->pend[i].t_ns = fv_i64_add_sat(t, SCORE_HORIZON_NS);
    p->pend[i].context = fv_gaze_context(p, p->state);
    p->pend[i].chosen = fv_gaze_select_candidate(p, p->state);
    double extra;
    fv_gaze_candidates(p, p->state, (double)SCORE_HORIZON_NS * 1e-9, p->pend[i].c, &extra);
}

/* The candidate predict() uses in state ev: the model until the context (or its state) has SCORE_MIN scores; then
 * the newest sample unless a candidate's mean error stays below the sample's by SELECT_SES standard errors of the
 * paired difference (the one with the lowest upper bound): a tie, or a gain within the scores' noise, is the latest
 * sample itself, exactly. */
int fv_gaze_select_candidate(const fv_gaze_pipeline *p, fv_gaze_event ev)
{
    int cx = fv_gaze_context(p, ev), st = cx / SPEED_BINS;
    const double *dm = NULL, *dq = NULL;
    double n = 0.0;
    if (p->scored[cx] >= SCORE_MIN) dm = p->dmean[cx], dq = p->dsq[cx], n = p->scored[cx];
    else if (p->scored_state[st] >= SCORE_MIN) dm = p->dmean_state[st], dq = p->dsq_state[st], n = p->scored_state[st];
    if (!dm) return CAND_MODEL;
    n = fmin(n, SCORE_MEMORY);
    int best = CAND_SAMPLE;
    double best_ub = 0.0;
    for (int c = 0; c < CANDS; c++) {
        double var = fmax(0.0, dq[c] - dm[c] * dm[c]);
        double ub = dm[c] + SELECT_SES * sqrt(var / n);
        if (ub < best_ub) best = c, best_ub = ub;
    }
    return best;
}

