/* @brief USB hotplug watcher: a libusb context, one event thread, one callback that only sets a flag. */
#include "fv_usb_hotplug.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

#include <libusb.h>

#include "fv_hid_eyetracker.h"
#include "fv_log.h"

#define MOD "usb"

struct fv_usb_hotplug {
    libusb_context *ctx;
    libusb_hotplug_callback_handle handle;
    bool registered, thread_started;
    pthread_t thread;
    atomic_int stop;
    atomic_int reprobe;
    atomic_uint_fast64_t events;
};

void fv_usb_hotplug_note(fv_usb_hotplug *h, uint16_t vid, uint16_t pid, uint8_t device_class, bool arrived)
{
    (void)arrived;
    const fv_hid_quirk *q = fv_hid_quirk_find(vid, pid);
    if (device_class != LIBUSB_CLASS_PER_INTERFACE && device_class != LIBUSB_CLASS_HID && !q) return;
    atomic_fetch_add(&h->events, 1);
    atomic_store(&h->reprobe, 1);
}

/* Runs on the event thread inside libusb: no blocking work, no libusb calls that do I/O. The device descriptor is
 * cached by libusb, so reading it here does not touch the bus. */
static int LIBUSB_CALL on_hotplug(libusb_context *ctx, libusb_device *dev, libusb_hotplug_event event, void *user)
{
    (void)ctx;
    struct libusb_device_descriptor dd;
    if (libusb_get_device_descriptor(dev, &dd) == 0)
        fv_usb_hotplug_note(user, dd.idVendor, dd.idProduct, dd.bDeviceClass,
                            event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED);
    return 0; /* keep the callback registered */
}

static void *event_thread(void *arg)
{
    fv_usb_hotplug *h = arg;
    while (!atomic_load(&h->stop)) {
        struct timeval tv = {0, 100000}; /* wake at least every 100 ms to see `stop` */
        libusb_handle_events_timeout_completed(h->ctx, &tv, NULL);
    }
    return NULL;
}

fv_result fv_usb_hotplug_start(fv_usb_hotplug **out)
{
    fv_result r = FV_OK;
    fv_usb_hotplug *h = calloc(1, sizeof *h);
    if (!h) return FV_ERR_NO_MEMORY;
    atomic_init(&h->stop, 0);
    atomic_init(&h->reprobe, 0);
    atomic_init(&h->events, 0);
    int rc = libusb_init(&h->ctx);
    if (rc != 0) {
        FV_INFO(MOD, "libusb unavailable (%s): no USB hotplug", libusb_error_name(rc));
        h->ctx = NULL;
        r = FV_ERR_UNSUPPORTED;
        goto fail;
    }
    if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) {
        FV_INFO(MOD, "libusb has no hotplug support here");
        r = FV_ERR_UNSUPPORTED;
        goto fail;
    }
    rc = libusb_hotplug_register_callback(h->ctx, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED | LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT,
                                          0, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
                                          LIBUSB_HOTPLUG_MATCH_ANY, on_hotplug, h, &h->handle);
    if (rc != LIBUSB_SUCCESS) {
        FV_ERROR(MOD, "libusb_hotplug_register_callback failed: %s", libusb_error_name(rc));
        r = FV_ERR_IO;
        goto fail;
    }
    h->registered = true;
    if (pthread_create(&h->thread, NULL, event_thread, h) != 0) {
        FV_ERROR(MOD, "cannot start the USB event thread");
        r = FV_ERR_NO_MEMORY;
        goto fail;
    }
    h->thread_started = true;
    *out = h;
    return FV_OK;
fail:
    fv_usb_hotplug_stop(&h);
    return r;
}

void fv_usb_hotplug_stop(fv_usb_hotplug **hp)
{
    if (!hp || !*hp) return;
    fv_usb_hotplug *h = *hp;
    atomic_store(&h->stop, 1);
    /* Deregistering wakes the event handler, so the thread sees `stop` promptly. */
    if (h->registered) libusb_hotplug_deregister_callback(h->ctx, h->handle);
    if (h->thread_started) pthread_join(h->thread, NULL);
    if (h->ctx) libusb_exit(h->ctx);
    free(h);
    *hp = NULL;
}

bool fv_usb_hotplug_take_reprobe(fv_usb_hotplug *h) { return atomic_exchange(&h->reprobe, 0) != 0; }

uint64_t fv_usb_hotplug_events(const fv_usb_hotplug *h)
{
    return atomic_load(&((fv_usb_hotplug *)h)->events);
}
