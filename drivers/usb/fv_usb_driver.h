/* @brief The `usb` driver: HID-class eye trackers read through libusb (GET_DESCRIPTOR 0x22, interrupt-IN reports,
 * GET/SET_REPORT for features) when hidraw is not usable (permissions, no hid driver bound). The bytes feed the same
 * HID parser and page-0x12 decoder as the `hid` driver. URIs: "usb:auto", "usb:VID:PID[:serial]". */
#ifndef FV_USB_DRIVER_H
#define FV_USB_DRIVER_H

#include "fovea/fv_device.h"
#include "fv_hid_transport.h"

extern const fv_driver fv_usb_driver;

/** Open the first HID interface of the first device matching vid:pid (and serial when not NULL/empty) as a HID
 *  transport. FV_ERR_NOT_FOUND when absent, FV_ERR_IO (logged, with the udev hint on EACCES) otherwise. */
FV_MUST_CHECK fv_result fv_usb_transport_open(uint16_t vid, uint16_t pid, const char *serial, fv_hid_transport **out);

#endif
