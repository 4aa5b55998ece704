/* @brief Spaces: reference spaces VIEW / LOCAL / STAGE (and LOCAL_FLOOR, XR_EXT_local_floor), action spaces (the eye
 * gaze pose from fovea's gaze pipeline, predicted to the requested time), xrLocateSpace and xrLocateViews from
 * fovea's head pose and the HMD profile's field of view. Every pose is computed in LOCAL ("the world") and related
 * by pose algebra. The head is static today (no head tracker): valid, not tracked. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fv_math.h"
#include "xr_internal.h"

/* chosen: a standing eye height above the floor, metres (STAGE and LOCAL_FLOOR lie this far below LOCAL) */
#define FV_XR_EYE_HEIGHT_M 1.6f
/* chosen: the stage's extent when there is no guardian (2 m x 2 m around the start) */
#define FV_XR_STAGE_SIZE_M 2.0f
/* the IPD the views are built with when the HMD profile has none: the population mean */
#define FV_XR_IPD_M 0.063f

struct fv_xr_space_list; /* spaces hang off the session as a list of XrSpace_T (struct only named for the header) */

static fv_quat q_of(XrQuaternionf q) { return (fv_quat){q.x, q.y, q.z, q.w}; }
static XrQuaternionf xq(fv_quat q) { return (XrQuaternionf){q.x, q.y, q.z, q.w}; }
static fv_vec3 v_of(XrVector3f v) { return (fv_vec3){v.x, v.y, v.z}; }
static XrVector3f xv(fv_vec3 v) { return (XrVector3f){v.x, v.y, v.z}; }

/* a * b: b expressed in a's frame, then into a's parent */
static XrPosef pose_mul(XrPosef a, XrPosef b)
{
    XrPosef r;
    r.orientation = xq(fv_quat_normalize(fv_quat_mul(q_of(a.orientation), q_of(b.orientation))));
    r.position = xv(fv_v3_add(v_of(a.position), fv_quat_rotate(q_of(a.orientation), v_of(b.position))));
    return r;
}

static XrPosef pose_inv(XrPosef a)
{
    fv_quat qi = {-a.orientation.x, -a.orientation.y, -a.orientation.z, a.orientation.w};
    XrPosef r;
    r.orientation = xq(qi);
    r.position = xv(fv_v3_scale(fv_quat_rotate(qi, v_of(a.position)), -1.0f));
    return r;
}

static const XrPosef POSE_IDENTITY = {{0, 0, 0, 1}, {0, 0, 0}};

void fv_xr_head_pose(struct XrInstance_T *inst, XrTime t, XrPosef *out)
{
    (void)t;
    *out = POSE_IDENTITY; /* LOCAL is where the head started */
    float q[4], p[3];
    /* a tracker that records the head (FOVEA_XR_GAZE=trace:... of SRanipal, Pico or fovea's format) moves it, as
     * `fovea run --head trace` does: the eyes' views and the gaze ray ride on it, the gaze never turns against them */
    if (inst && inst->gaze && fv_xr_gaze_head(inst->gaze, q, p)) {
        out->orientation = (XrQuaternionf){q[0], q[1], q[2], q[3]};
        out->position = (XrVector3f){p[0], p[1], p[2]};
    }
}

static bool ref_type_supported(struct XrSession_T *s, XrReferenceSpaceType t)
{
    if (t == XR_REFERENCE_SPACE_TYPE_VIEW || t == XR_REFERENCE_SPACE_TYPE_LOCAL || t == XR_REFERENCE_SPACE_TYPE_STAGE)
        return true;
    if (t == XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO) return s->inst->ext.foveated; /* the rendering gaze */
    return t == XR_REFERENCE_SPACE_TYPE_LOCAL_FLOOR_EXT && s->inst->ext.local_floor;
}

FV_XR_DECL(xrEnumerateReferenceSpaces)(XrSession session, uint32_t cap, uint32_t *count, XrReferenceSpaceType *types)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!count || (cap && !types)) return XR_ERROR_VALIDATION_FAILURE;
    XrReferenceSpaceType all[5] = {XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL,
                                   XR_REFERENCE_SPACE_TYPE_STAGE};
    uint32_t n = 3;
    if (s->inst->ext.local_floor) all[n++] = XR_REFERENCE_SPACE_TYPE_LOCAL_FLOOR_EXT;
    if (s->inst->ext.foveated) all[n++] = XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO;
    *count = n;
    if (cap == 0) return XR_SUCCESS;
    if (cap < n) return XR_ERROR_SIZE_INSUFFICIENT;
    memcpy(types, all, n * sizeof all[0]);
    return XR_SUCCESS;
}

static XrResult space_add(struct XrSession_T *s, struct XrSpace_T *sp, XrSpace *out)
{
    fv_xr_handle_add(sp);
    if (!fv_xr_handle_live(sp, FV_XR_MAGIC_SPACE)) {
        free(sp);
        return XR_ERROR_OUT_OF_MEMORY;
    }
    sp->next = (struct XrSpace_T *)s->spaces;
    s->spaces = (struct fv_xr_space_list *)sp;
    *out = sp;
    return XR_SUCCESS;
}

FV_XR_DECL(xrCreateReferenceSpace)(XrSession session, const XrReferenceSpaceCreateInfo *info, XrSpace *out)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_REFERENCE_SPACE_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    if (fv_xr_chain_check(info->next, "xrCreateReferenceSpace") != XR_SUCCESS) return XR_ERROR_VALIDATION_FAILURE;
    /* any type this session does not offer, known to fovea or not (the spec; the conformance suite asks it) */
    if (!ref_type_supported(s, info->referenceSpaceType)) return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    if (!fv_xr_pose_valid(&info->poseInReferenceSpace)) return XR_ERROR_POSE_INVALID;
    struct XrSpace_T *sp = calloc(1, sizeof *sp);
    if (!sp) return XR_ERROR_OUT_OF_MEMORY;
    sp->magic = FV_XR_MAGIC_SPACE;
    sp->session = s;
    sp->kind = FV_XR_SPACE_REFERENCE;
    sp->ref_type = info->referenceSpaceType;
    sp->offset = info->poseInReferenceSpace;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = space_add(s, sp, out);
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

FV_XR_DECL(xrGetReferenceSpaceBoundsRect)(XrSession session, XrReferenceSpaceType type, XrExtent2Df *bounds)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!bounds) return XR_ERROR_VALIDATION_FAILURE;
    if (!ref_type_supported(s, type)) return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    if (type == XR_REFERENCE_SPACE_TYPE_STAGE) {
        bounds->width = bounds->height = FV_XR_STAGE_SIZE_M;
        return XR_SUCCESS;
    }
    bounds->width = bounds->height = 0;
    return XR_SPACE_BOUNDS_UNAVAILABLE;
}

FV_XR_DECL(xrCreateActionSpace)(XrSession session, const XrActionSpaceCreateInfo *info, XrSpace *out)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || !out || info->type != XR_TYPE_ACTION_SPACE_CREATE_INFO ||
        fv_xr_chain_check(info->next, "xrCreateActionSpace") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    if (!fv_xr_pose_valid(&info->poseInActionSpace)) return XR_ERROR_POSE_INVALID;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = fv_xr_input_check_space(s, info);
    if (r == XR_SUCCESS) {
        struct XrSpace_T *sp = calloc(1, sizeof *sp);
        if (!sp) r = XR_ERROR_OUT_OF_MEMORY;
        else {
            sp->magic = FV_XR_MAGIC_SPACE;
            sp->session = s;
            sp->kind = FV_XR_SPACE_ACTION;
            sp->action = info->action;
            sp->subaction_path = info->subactionPath;
            sp->offset = info->poseInActionSpace;
            r = space_add(s, sp, out);
        }
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

static void space_unlink(struct XrSession_T *s, struct XrSpace_T *sp)
{
    struct XrSpace_T **pp = (struct XrSpace_T **)&s->spaces;
    while (*pp && *pp != sp) pp = &(*pp)->next;
    if (*pp) *pp = sp->next;
}

FV_XR_DECL(xrDestroySpace)(XrSpace space)
{
    if (!fv_xr_handle_live(space, FV_XR_MAGIC_SPACE)) return XR_ERROR_HANDLE_INVALID;
    struct XrSpace_T *sp = space;
    struct XrSession_T *s = sp->session;
    pthread_mutex_lock(&s->inst->lock);
    fv_xr_handle_remove(sp);
    space_unlink(s, sp);
    pthread_mutex_unlock(&s->inst->lock);
    sp->magic = 0;
    free(sp);
    return XR_SUCCESS;
}

void fv_xr_spaces_destroy_all(struct XrSession_T *s)
{
    struct XrSpace_T *sp = (struct XrSpace_T *)s->spaces;
    while (sp) {
        struct XrSpace_T *n = sp->next;
        fv_xr_handle_remove(sp);
        sp->magic = 0;
        free(sp);
        sp = n;
    }
    s->spaces = NULL;
}

#define LOC_VALID (XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT)
#define LOC_TRACKED (XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT)

/* The head's own flags in LOCAL: valid, not tracked (no head tracker in fovea today). */
#define HEAD_FLAGS LOC_VALID

XrSpaceLocationFlags fv_xr_space_pose(struct XrSpace_T *sp, XrTime t, XrPosef *out, bool *out_on_head)
{
    XrPosef base = POSE_IDENTITY;
    XrSpaceLocationFlags flags = LOC_VALID | LOC_TRACKED;
    bool on_head = false;
    struct XrInstance_T *inst = sp->session->inst;
    if (sp->kind == FV_XR_SPACE_REFERENCE) {
        if (sp->ref_type == XR_REFERENCE_SPACE_TYPE_VIEW) {
            fv_xr_head_pose(inst, t, &base);
            on_head = true; /* exactly the head: its relation to the head is known */
        } else if (sp->ref_type == XR_REFERENCE_SPACE_TYPE_STAGE ||
                   sp->ref_type == XR_REFERENCE_SPACE_TYPE_LOCAL_FLOOR_EXT) {
            base.position.y = -FV_XR_EYE_HEIGHT_M;
        }
    }
    /* the eye gaze action space, and XR_VARJO_foveated_rendering's COMBINED_EYE space (the rendering gaze: the same
     * predicted ray; its ORIENTATION_TRACKED bit says whether the insets follow the gaze) */
    bool combined_eye = sp->kind == FV_XR_SPACE_REFERENCE && sp->ref_type == XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO;
    if (sp->kind != FV_XR_SPACE_REFERENCE || combined_eye) {
        flags = 0;
        on_head = true; /* the gaze is measured in the head frame */
        if ((combined_eye || fv_xr_input_space_source(sp) == 1 /* FV_XR_POSE_EYE_GAZE */) && inst->gaze) {
            /* the gaze ray in the head frame, predicted by fovea's pipeline to t, then into LOCAL with the head */
            float o[3], d[3];
            bool tracked = fv_xr_gaze_predict(inst->gaze, t, o, d);
            if (tracked || isfinite(d[0])) {
                /* orientation: the rotation taking the pose's -z (forward) onto the gaze direction */
                fv_vec3 dir = fv_v3_normalize_or(fv_v3(d[0], d[1], d[2]), fv_v3(0, 0, -1));
                fv_vec3 fwd = fv_v3(0, 0, -1);
                fv_vec3 axis = fv_v3_cross(fwd, dir);
                float c = fwd.x * dir.x + fwd.y * dir.y + fwd.z * dir.z;
                fv_quat q;
                float al = sqrtf(axis.x * axis.x + axis.y * axis.y + axis.z * axis.z);
                if (al < 1e-7f) q = c > 0 ? fv_quat_identity() : fv_quat_axis_angle(fv_v3(0, 1, 0), 3.14159265f);
                else q = fv_quat_axis_angle(fv_v3_scale(axis, 1.0f / al), atan2f(al, c));
                XrPosef head, gaze = {xq(q), {o[0], o[1], o[2]}};
                fv_xr_head_pose(inst, t, &head);
                base = pose_mul(head, gaze);
                flags = LOC_VALID | (tracked ? LOC_TRACKED : 0);
            }
        }
    }
    *out = pose_mul(base, sp->offset);
    if (out_on_head) *out_on_head = on_head;
    return flags;
}

XrSpaceLocationFlags fv_xr_space_relate(struct XrSpace_T *a, struct XrSpace_T *b, XrTime t, XrPosef *out_a_in_b)
{
    XrPosef pa, pb;
    bool ha, hb;
    XrSpaceLocationFlags f = fv_xr_space_pose(a, t, &pa, &ha) & fv_xr_space_pose(b, t, &pb, &hb);
    /* a relation through the head carries the head's own tracking, unless both ends ride on the head */
    if (ha != hb) f &= HEAD_FLAGS;
    if (!(f & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT) || !(f & XR_SPACE_LOCATION_POSITION_VALID_BIT)) {
        *out_a_in_b = POSE_IDENTITY;
        return 0;
    }
    *out_a_in_b = pose_mul(pose_inv(pb), pa);
    return f;
}

FV_XR_DECL(xrLocateSpace)(XrSpace space, XrSpace base, XrTime time, XrSpaceLocation *location)
{
    if (!fv_xr_handle_live(space, FV_XR_MAGIC_SPACE) || !fv_xr_handle_live(base, FV_XR_MAGIC_SPACE))
        return XR_ERROR_HANDLE_INVALID;
    struct XrSpace_T *a = space, *b = base;
    if (a->session != b->session) return XR_ERROR_VALIDATION_FAILURE;
    if (!location || location->type != XR_TYPE_SPACE_LOCATION) return XR_ERROR_VALIDATION_FAILURE;
    XrSpaceVelocity *vel = NULL;
    if (fv_xr_chain_find(location->next, XR_TYPE_SPACE_VELOCITY, "xrLocateSpace", (const void **)&vel) != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    if (time <= 0) return XR_ERROR_TIME_INVALID;
    struct XrSession_T *s = a->session;
    pthread_mutex_lock(&s->inst->lock);
    XrResult r = s->loss_pending ? XR_ERROR_SESSION_LOST : XR_SUCCESS;
    if (r == XR_SUCCESS) {
        XrSpaceLocationFlags f = fv_xr_space_relate(a, b, time, &location->pose);
        location->locationFlags = f;
        if (vel) {
            /* reference spaces and the static head do not move relative to each other; gaze velocity is unknown */
            bool both_ref = a->kind == FV_XR_SPACE_REFERENCE && b->kind == FV_XR_SPACE_REFERENCE;
            vel->linearVelocity = (XrVector3f){0, 0, 0};
            vel->angularVelocity = (XrVector3f){0, 0, 0};
            vel->velocityFlags =
                both_ref && (f & LOC_VALID) ? XR_SPACE_VELOCITY_LINEAR_VALID_BIT | XR_SPACE_VELOCITY_ANGULAR_VALID_BIT : 0;
        }
    }
    pthread_mutex_unlock(&s->inst->lock);
    return r;
}

FV_XR_DECL(xrLocateViews)(XrSession session, const XrViewLocateInfo *info, XrViewState *state, uint32_t cap,
                          uint32_t *count, XrView *views)
{
    struct XrSession_T *s = fv_xr_session_check(session);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_VIEW_LOCATE_INFO || !state || state->type != XR_TYPE_VIEW_STATE || !count ||
        (cap && !views))
        return XR_ERROR_VALIDATION_FAILURE;
    if (fv_xr_chain_check(info->next, "xrLocateViews") != XR_SUCCESS ||
        fv_xr_chain_check(state->next, "xrLocateViews: XrViewState") != XR_SUCCESS)
        return XR_ERROR_VALIDATION_FAILURE;
    if (!fv_xr_handle_live(info->space, FV_XR_MAGIC_SPACE) || ((struct XrSpace_T *)info->space)->session != s)
        return XR_ERROR_HANDLE_INVALID;
    if (info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
    uint32_t n = 0;
    XrResult r = fv_xr_check_view_config(s->inst, info->viewConfigurationType, &n);
    if (r != XR_SUCCESS) return r;
    if (s->view_count && info->viewConfigurationType != s->view_config) return XR_ERROR_VALIDATION_FAILURE;
    *count = n;
    if (cap == 0) return XR_SUCCESS;
    if (cap < n) return XR_ERROR_SIZE_INSUFFICIENT;
    pthread_mutex_lock(&s->inst->lock);
    if (s->loss_pending) {
        pthread_mutex_unlock(&s->inst->lock);
        return XR_ERROR_SESSION_LOST;
    }
    XrPosef head, base;
    bool base_on_head;
    fv_xr_head_pose(s->inst, info->displayTime, &head);
    XrSpaceLocationFlags fb = fv_xr_space_pose(info->space, info->displayTime, &base, &base_on_head);
    if (!base_on_head) fb &= HEAD_FLAGS; /* the eyes ride on the head */
    XrPosef base_inv = pose_inv(base);
    const fv_hmd_profile *h = &s->inst->hmd;
    for (uint32_t i = 0; i < n; i++) {
        if (views[i].type != XR_TYPE_VIEW || fv_xr_chain_check(views[i].next, "xrLocateViews: XrView") != XR_SUCCESS) {
            pthread_mutex_unlock(&s->inst->lock);
            return XR_ERROR_VALIDATION_FAILURE;
        }
        /* quad views (XR_VARJO_quad_views): 2 and 3 are the left and right eyes' insets */
        XrPosef eye = {{0, 0, 0, 1}, {((i & 1u) == 0 ? -0.5f : 0.5f) * FV_XR_IPD_M, 0, 0}};
        views[i].pose = pose_mul(base_inv, pose_mul(head, eye));
        const fv_hmd_fov *f = &h->fov[i & 1u];
        views[i].fov.angleLeft = -atanf(f->tan_left);
        views[i].fov.angleRight = atanf(f->tan_right);
        views[i].fov.angleUp = atanf(f->tan_up);
        views[i].fov.angleDown = -atanf(f->tan_down);
    }
    if (n == 4) fv_xr_quad_locate(s, info, views);
    /* relative to a space off the head, the head's tracking decides (given, not tracked today) */
    state->viewStateFlags = 0;
    if ((fb & LOC_VALID) == LOC_VALID)
        state->viewStateFlags = XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                                ((fb & LOC_TRACKED) == LOC_TRACKED
                                     ? XR_VIEW_STATE_ORIENTATION_TRACKED_BIT | XR_VIEW_STATE_POSITION_TRACKED_BIT
                                     : 0);
    pthread_mutex_unlock(&s->inst->lock);
    return XR_SUCCESS;
}
