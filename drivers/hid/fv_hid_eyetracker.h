/* @brief The Eye and Head Trackers usage page (0x12, HUTRR74) mapped onto fv_gaze_sample: Tracking Data input,
 * Capabilities / Configuration / Status features, and the Device Mode Request control the host must write before
 * gaze flows. Pure functions on a parsed descriptor and report bytes: no I/O, no clock, no allocation.
 *
 * Frames (fovea's reading of HUTRR74 and Microsoft's GazeHid drivers, see docs/hid.md):
 *  - Gaze Point: on the calibrated screen plane, origin at its top-left corner, +x right, +y down.
 *  - Eye and head positions: the tracker frame, origin at the centre of the calibrated screen, +x right, +y up,
 *    +z out of the screen towards the user.
 *  - A per-device fv_hid_screen_config places the tracker frame in fovea's head frame. */
#ifndef FV_HID_EYETRACKER_H
#define FV_HID_EYETRACKER_H

#include <stdbool.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"
#include "fv_hid_descriptor.h"
#include "fv_math.h"

#define FV_HID_PAGE_EYE_HEAD_TRACKERS 0x12u
#define FV_HID_USAGE(page, id) (((uint32_t)(page) << 16) | (uint32_t)(id))
#define FV_HID_ET(id) FV_HID_USAGE(FV_HID_PAGE_EYE_HEAD_TRACKERS, id)

/** fovea's documented vendor extension for pupil diameter (page 0x12 has no pupil usage): on vendor page 0xFF12, a
 *  Pupil Data physical collection (0x01) holding Left (0x10) and Right (0x11) Pupil Diameter, length units
 *  (e.g. cm e-4 = µm), in the Tracking Data input report. Out-of-range values mean "no pupil". */
#define FV_HID_FOVEA_VENDOR_PAGE 0xFF12u
#define FV_HID_FOVEA_USAGE_PUPIL FV_HID_USAGE(FV_HID_FOVEA_VENDOR_PAGE, 0x01)
#define FV_HID_FOVEA_USAGE_PUPIL_LEFT FV_HID_USAGE(FV_HID_FOVEA_VENDOR_PAGE, 0x10)
#define FV_HID_FOVEA_USAGE_PUPIL_RIGHT FV_HID_USAGE(FV_HID_FOVEA_VENDOR_PAGE, 0x11)

/** Device Mode Request bits (GazeHid inc/Tracker.h). */
enum {
    FV_HID_MODE_GAZE_POINT = 1,
    FV_HID_MODE_EYE_POSITION = 2,
    FV_HID_MODE_HEAD_POSITION = 4,
    FV_HID_MODE_ALL = 7,
};

/** Configuration Status values. */
enum {
    FV_HID_STATUS_RESERVED = 0,
    FV_HID_STATUS_READY = 1,
    FV_HID_STATUS_CONFIGURING = 2,
    FV_HID_STATUS_SCREEN_SETUP_NEEDED = 3,
    FV_HID_STATUS_USER_CALIBRATION_NEEDED = 4,
};

/** A vendor quirk: a device known by VID/PID, with vendor usages for what page 0x12 lacks. Static data. */
typedef struct fv_hid_quirk {
    uint16_t vid, pid;
    const char *name;
    uint32_t pupil_usage[2];  /* extended usages of left/right pupil diameter (0: none) */
    float pupil_unitless_mm;  /* mm per physical unit when the pupil field declares no length unit (0: reject) */
    bool eye_tracker;         /* take the device for an eye tracker even if probing by usage page fails */
} fv_hid_quirk;

/** The quirks table entry of a VID/PID, or NULL. */
const fv_hid_quirk *fv_hid_quirk_find(uint16_t vid, uint16_t pid);
/** The whole table (for docs and `fovea devices`); *out_count entries. */
const fv_hid_quirk *fv_hid_quirk_table(size_t *out_count);

/** Where one value lives: field index into the descriptor (-1: absent) and element index. */
typedef struct fv_hid_ref {
    int16_t field;
    uint16_t index;
} fv_hid_ref;

/** Page-0x12 layout of one descriptor, resolved once. Plain data. */
typedef struct fv_hid_eyetracker_map {
    const fv_hid_quirk *quirk;
    uint8_t tracking_id;           /* report ID of Tracking Data (input) */
    fv_hid_ref timestamp;          /* Sensor Timestamp (usually 8 x 8 bits = 64-bit µs) */
    fv_hid_ref gaze[2];            /* Gaze Point X, Y */
    fv_hid_ref eye[2][3];          /* Left/Right Eye Position X, Y, Z */
    fv_hid_ref head_pos[3];        /* Head Position X, Y, Z */
    fv_hid_ref head_rot[3];        /* Head Direction: rotation about X, Y, Z */
    fv_hid_ref pupil[2];           /* vendor pupil diameter (quirk or fovea's extension) */
    fv_hid_ref quality, min_distance, optimum_distance, max_distance, max_screen_width, max_screen_height;
    fv_hid_ref display_manufacturer, display_product, display_serial, display_date;
    fv_hid_ref calibrated_width, calibrated_height;
    fv_hid_ref status_config[2], status_frequency[2]; /* [0] feature, [1] input */
    fv_hid_ref mode_request;
} fv_hid_eyetracker_map;

/** True when the descriptor has a top-level Application collection Eye Tracker (0x12:0x01). */
bool fv_hid_is_eye_tracker(const fv_hid_descriptor *d);

/** Resolve the page-0x12 layout. FV_ERR_UNSUPPORTED (logged with the reason) when the descriptor is not an eye
 *  tracker (and no quirk says it is) or lacks a Tracking Data input report with Sensor Timestamp and Gaze Point.
 *  quirk may be NULL; fovea's own vendor pupil usages are honoured for any device. */
FV_MUST_CHECK fv_result fv_hid_eyetracker_map_init(const fv_hid_descriptor *d, const fv_hid_quirk *quirk,
                                                   fv_hid_eyetracker_map *out);

/** Per-device placement of the tracker frame in the head frame (see the file comment). Zero is not a valid config:
 *  start from fv_hid_screen_config_defaults(). */
typedef struct fv_hid_screen_config {
    fv_vec3 screen_center_head_mm; /* tracker-frame origin in the head frame */
    fv_quat tracker_to_head;       /* rotation of tracker-frame axes into the head frame */
    float width_mm, height_mm;     /* calibrated screen size; 0 = from the Configuration feature report */
    fv_vec3 default_eye_head_mm[2]; /* eye positions assumed when the tracker sends none */
} fv_hid_screen_config;

/** Defaults: a desktop screen 650 mm in front of the head, facing it (identity rotation), eyes at ±32 mm. */
void fv_hid_screen_config_defaults(fv_hid_screen_config *c);

/** Decode one Tracking Data input report (ID byte first when the descriptor uses IDs) into *out: t_device_ns from the
 *  Sensor Timestamp, per-eye and combined rays in the head frame, screen point, head pose, pupil via quirks. Values
 *  out of their logical range leave that part invalid (NaN, flag clear). t_host_ns and seq are left for the caller.
 *  FV_ERR_PROTOCOL (logged) when the report has the wrong ID or length. */
FV_MUST_CHECK fv_result fv_hid_eyetracker_decode_tracking(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                                          const fv_hid_screen_config *screen, const uint8_t *report,
                                                          size_t len, fv_gaze_sample *out);

/** Capabilities feature report (0x11). Distances in mm, NaN when absent or out of range. */
typedef struct fv_hid_capabilities {
    int tracker_quality; /* -1 when absent */
    double min_distance_mm, optimum_distance_mm, max_distance_mm;
    double max_screen_width_mm, max_screen_height_mm;
} fv_hid_capabilities;

/** Configuration feature report (0x12). */
typedef struct fv_hid_configuration {
    int64_t display_manufacturer, display_product, display_serial, display_date; /* -1 when absent */
    double calibrated_width_mm, calibrated_height_mm;                           /* NaN when absent */
} fv_hid_configuration;

/** Status report (0x13, input or feature). */
typedef struct fv_hid_status {
    int configuration_status; /* FV_HID_STATUS_*, -1 when absent */
    double sampling_frequency_hz; /* NaN when absent */
} fv_hid_status;

FV_MUST_CHECK fv_result fv_hid_eyetracker_decode_capabilities(const fv_hid_descriptor *d,
                                                              const fv_hid_eyetracker_map *m, const uint8_t *report,
                                                              size_t len, fv_hid_capabilities *out);
FV_MUST_CHECK fv_result fv_hid_eyetracker_decode_configuration(const fv_hid_descriptor *d,
                                                               const fv_hid_eyetracker_map *m, const uint8_t *report,
                                                               size_t len, fv_hid_configuration *out);
/** type: FV_HID_REPORT_FEATURE or FV_HID_REPORT_INPUT (the same ID is declared as both). */
FV_MUST_CHECK fv_result fv_hid_eyetracker_decode_status(const fv_hid_descriptor *d, const fv_hid_eyetracker_map *m,
                                                        fv_hid_report_type type, const uint8_t *report, size_t len,
                                                        fv_hid_status *out);
/** Build the Control feature report carrying a Device Mode Request (FV_HID_MODE_* bits). */
FV_MUST_CHECK fv_result fv_hid_eyetracker_encode_mode_request(const fv_hid_descriptor *d,
                                                              const fv_hid_eyetracker_map *m, unsigned mode,
                                                              uint8_t *buf, size_t cap, size_t *out_len);

/** Check a report against the descriptor: known ID for this type and exact length. FV_ERR_PROTOCOL (logged with
 *  the ID, the length and what was expected) otherwise; *out_report names it on success. */
FV_MUST_CHECK fv_result fv_hid_report_check(const fv_hid_descriptor *d, fv_hid_report_type type,
                                            const uint8_t *report, size_t len, const fv_hid_report **out_report);

#endif
