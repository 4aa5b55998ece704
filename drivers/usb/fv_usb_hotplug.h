/* @brief USB hotplug: libusb_hotplug_register_callback (when LIBUSB_CAP_HAS_HOTPLUG) with its own event thread and a
 * minimal callback that does no blocking work: it only flags that the device list should be probed again. */
#ifndef FV_USB_HOTPLUG_H
#define FV_USB_HOTPLUG_H

#include <stdbool.h>
#include <stdint.h>

#include "fv_result.h"

typedef struct fv_usb_hotplug fv_usb_hotplug;

/** Start watching. FV_ERR_UNSUPPORTED (logged at info) when libusb cannot start or has no hotplug here. */
FV_MUST_CHECK fv_result fv_usb_hotplug_start(fv_usb_hotplug **out);
/** Stop the event thread and free; safe on NULL. */
void fv_usb_hotplug_stop(fv_usb_hotplug **h);
/** True once after one or more arrivals/removals of a possible tracker (HID-class or in the quirks table). Any
 *  thread. */
bool fv_usb_hotplug_take_reprobe(fv_usb_hotplug *h);
/** Events flagged so far. */
uint64_t fv_usb_hotplug_events(const fv_usb_hotplug *h);
/** The callback's whole body (exposed so tests can drive it without hardware): flags a re-probe when the device
 *  could be a tracker. device_class is bDeviceClass (0: per interface, 3: HID). */
void fv_usb_hotplug_note(fv_usb_hotplug *h, uint16_t vid, uint16_t pid, uint8_t device_class, bool arrived);

#endif
