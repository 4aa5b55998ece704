/* @brief Names of HID usage pages and of the usages fovea meets (HID Usage Tables 1.5; page 0x12 from HUTRR74),
 * plus fovea's vendor page for pupil diameter (documented in docs/hid.md). */
#include <stddef.h>
#include <stdint.h>

#include "fv_hid_descriptor.h"
#include "fv_hid_eyetracker.h"

typedef struct name_entry {
    uint32_t key;
    const char *name;
} name_entry;

static const name_entry g_pages[] = {
    {0x01, "Generic Desktop"}, {0x02, "Simulation Controls"}, {0x03, "VR Controls"}, {0x06, "Generic Device Controls"},
    {0x07, "Keyboard/Keypad"}, {0x08, "LED"}, {0x09, "Button"}, {0x0B, "Telephony"}, {0x0C, "Consumer"},
    {0x0D, "Digitizers"}, {0x0E, "Haptics"}, {0x0F, "Physical Input Device"}, {0x12, "Eye and Head Trackers"},
    {0x14, "Auxiliary Display"}, {0x20, "Sensors"}, {0x40, "Medical Instrument"}, {0x59, "Lighting and Illumination"},
    {0x84, "Power Device"}, {0x85, "Battery System"}, {FV_HID_FOVEA_VENDOR_PAGE, "fovea vendor (pupil)"},
};

static const name_entry g_usages[] = {
    /* Generic Desktop (a few, for the descriptors users paste first) */
    {0x00010001, "Pointer"}, {0x00010002, "Mouse"}, {0x00010004, "Joystick"}, {0x00010005, "Gamepad"},
    {0x00010006, "Keyboard"}, {0x00010030, "X"}, {0x00010031, "Y"}, {0x00010032, "Z"}, {0x00010033, "Rx"},
    {0x00010034, "Ry"}, {0x00010035, "Rz"}, {0x00010038, "Wheel"},
    /* Eye and Head Trackers (0x12) */
    {0x00120001, "Eye Tracker"}, {0x00120002, "Head Tracker"}, {0x00120010, "Tracking Data"},
    {0x00120011, "Capabilities"}, {0x00120012, "Configuration"}, {0x00120013, "Status"}, {0x00120014, "Control"},
    {0x00120020, "Sensor Timestamp"}, {0x00120021, "Position X"}, {0x00120022, "Position Y"},
    {0x00120023, "Position Z"}, {0x00120024, "Gaze Point"}, {0x00120025, "Left Eye Position"},
    {0x00120026, "Right Eye Position"}, {0x00120027, "Head Position"}, {0x00120028, "Head Direction"},
    {0x00120029, "Rotation about X axis"}, {0x0012002A, "Rotation about Y axis"},
    {0x0012002B, "Rotation about Z axis"}, {0x00120100, "Tracker Quality"},
    {0x00120101, "Minimum Tracking Distance"}, {0x00120102, "Optimum Tracking Distance"},
    {0x00120103, "Maximum Tracking Distance"}, {0x00120104, "Maximum Screen Plane Width"},
    {0x00120105, "Maximum Screen Plane Height"}, {0x00120200, "Display Manufacturer ID"},
    {0x00120201, "Display Product ID"}, {0x00120202, "Display Serial Number"},
    {0x00120203, "Display Manufacturer Date"}, {0x00120204, "Calibrated Screen Width"},
    {0x00120205, "Calibrated Screen Height"}, {0x00120300, "Sampling Frequency"},
    {0x00120301, "Configuration Status"}, {0x00120400, "Device Mode Request"},
    /* fovea's vendor extension */
    {FV_HID_FOVEA_USAGE_PUPIL, "Pupil Data"}, {FV_HID_FOVEA_USAGE_PUPIL_LEFT, "Left Pupil Diameter"},
    {FV_HID_FOVEA_USAGE_PUPIL_RIGHT, "Right Pupil Diameter"},
};

const char *fv_hid_usage_page_name(uint16_t page)
{
    for (size_t i = 0; i < sizeof g_pages / sizeof g_pages[0]; i++)
        if (g_pages[i].key == page) return g_pages[i].name;
    if (page >= 0xFF00) return "Vendor-defined";
    return NULL;
}

const char *fv_hid_usage_name(uint32_t usage)
{
    for (size_t i = 0; i < sizeof g_usages / sizeof g_usages[0]; i++)
        if (g_usages[i].key == usage) return g_usages[i].name;
    if ((usage >> 16) == 0x09 && (usage & 0xFFFFu) > 0) return "Button N";
    return NULL;
}
