/* @brief The Vulkan core and the frame image table on a device: asked-for extensions a device lacks make it unusable
 * with the reason named; a failing surface callback fails cleanly; the image table's barrier tracking keeps a
 * sequence of writes, reads and readbacks hazard-free under synchronization validation and returns what was
 * written; the compute-pass helper refuses a bad description. */
#include <stdlib.h>
#include <string.h>

#include "fv_images.h"
#include "fv_test.h"
#include "fv_vk.h"

static bool ci(void)
{
    const char *v = getenv("CI");
    return v && strcmp(v, "true") == 0;
}

/* A device with validation on, or a skip (a failure under CI=true). */
static fv_vk *open_vk(void)
{
    fv_vk *vk = NULL;
    fv_vk_desc d = {.validation = 1};
    if (fv_vk_create(&d, &vk) != FV_OK) {
        if (ci()) fail_msg("no usable Vulkan device and CI=true");
        skip();
    }
    return vk;
}

static void close_vk(fv_vk **vk)
{
    uint32_t n = fv_vk_validation_messages(*vk);
    fv_vk_destroy(vk);
    assert_int_equal(n, 0);
}

static void a_missing_device_extension_makes_every_device_unusable_and_says_which(void **state)
{
    (void)state;
    fv_vk_destroy(&(fv_vk *){open_vk()}); /* a device exists at all */
    const char *exts[1] = {"VK_FOVEA_no_such_extension"};
    fv_vk_desc d = {.validation = -1, .device_extensions = exts, .device_extension_count = 1};
    fv_vk *vk = NULL;
    fv_test_log_capture_begin();
    fv_result res = fv_vk_create(&d, &vk);
    fv_test_log_capture_end();
    assert_true(FV_FAILED(res));
    assert_null(vk);
    fv_assert_log_contains("lacks device extension VK_FOVEA_no_such_extension");
}

static void a_missing_instance_extension_is_refused_before_the_instance(void **state)
{
    (void)state;
    const char *exts[1] = {"VK_FOVEA_no_such_instance_extension"};
    fv_vk_desc d = {.validation = -1, .instance_extensions = exts, .instance_extension_count = 1};
    fv_vk *vk = NULL;
    fv_test_log_capture_begin();
    fv_result res = fv_vk_create(&d, &vk);
    fv_test_log_capture_end();
    assert_int_equal(res, FV_ERR_UNSUPPORTED);
    assert_null(vk);
    fv_assert_log_contains("lacks instance extension VK_FOVEA_no_such_instance_extension");
    /* More than the core holds: a range error, not an overflow. */
    const char *many[FV_VK_MAX_EXTENSIONS + 1];
    for (int i = 0; i <= FV_VK_MAX_EXTENSIONS; i++) many[i] = "VK_KHR_surface";
    d = (fv_vk_desc){.validation = -1, .device_extensions = many, .device_extension_count = FV_VK_MAX_EXTENSIONS + 1};
    fv_test_log_capture_begin();
    res = fv_vk_create(&d, &vk);
    fv_test_log_capture_end();
    assert_int_equal(res, FV_ERR_RANGE);
}

static fv_result failing_surface(VkInstance instance, void *user, VkSurfaceKHR *out)
{
    (void)instance;
    *out = VK_NULL_HANDLE;
    ++*(int *)user;
    return FV_ERR_UNSUPPORTED;
}

static void a_failing_surface_callback_fails_the_core_cleanly(void **state)
{
    (void)state;
    int calls = 0;
    fv_vk_desc d = {.validation = -1, .create_surface = failing_surface, .surface_user = &calls};
    fv_vk *vk = NULL;
    fv_test_log_capture_begin();
    fv_result res = fv_vk_create(&d, &vk);
    fv_test_log_capture_end();
    if (res == FV_ERR_UNSUPPORTED && strstr(fv_test_log_text(), "lacks instance extension")) skip(); /* no WSI */
    assert_int_equal(calls, 1);
    assert_int_equal(res, FV_ERR_UNSUPPORTED);
    assert_null(vk);
    fv_assert_log_contains("presentation surface could not be created");
}

static void image_table_tracks_writes_reads_and_readbacks_without_hazards(void **state)
{
    (void)state;
    fv_vk *vk = open_vk();
    fv_images t;
    assert_int_equal(fv_images_init(&t, vk, 8, 4), FV_OK);
    const fv_vk_image *color;
    assert_int_equal(fv_images_get(&t, FV_IMAGE_COLOR, &color), FV_OK);
    assert_int_equal(fv_images_layout(&t, FV_IMAGE_COLOR), VK_IMAGE_LAYOUT_UNDEFINED);
    float px[8 * 4 * 4];
    /* Nothing wrote it yet: a readback is refused. */
    fv_test_log_capture_begin();
    assert_int_equal(fv_images_read(&t, FV_IMAGE_COLOR, 0, px, sizeof px, 0, 8 * 16), FV_ERR_STATE);
    fv_test_log_capture_end();
    const fv_vk_image_use clear = {VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT};
    VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 2};
    for (int round = 0; round < 3; round++) {
        VkCommandBuffer cmd;
        assert_int_equal(fv_vk_oneshot_begin(vk, "tracker test", &cmd), FV_OK);
        /* write, write again (write-after-write), then a compute read and a transfer read of the same write */
        for (int k = 0; k < 2; k++) {
            fv_images_use(&t, cmd, FV_IMAGE_COLOR, clear);
            VkClearColorValue cv = {.float32 = {(float)round, (float)k, 0.5f, 1.0f}};
            vkCmdClearColorImage(cmd, color->image, VK_IMAGE_LAYOUT_GENERAL, &cv, 1, &all);
        }
        fv_images_use(&t, cmd, FV_IMAGE_COLOR,
                      (fv_vk_image_use){VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                        VK_ACCESS_SHADER_READ_BIT});
        assert_int_equal(fv_vk_oneshot_end(vk, cmd), FV_OK);
        assert_int_equal(fv_images_read(&t, FV_IMAGE_COLOR, 1, px, sizeof px, 0, 8 * 16), FV_OK);
        for (int i = 0; i < 8 * 4; i++) {
            assert_float_equal(px[4 * i + 0], (float)round, 0);
            assert_float_equal(px[4 * i + 1], 1.0f, 0);
        }
    }
    assert_int_equal(fv_images_layout(&t, FV_IMAGE_COLOR), VK_IMAGE_LAYOUT_GENERAL);
    /* Scratch images are added after the builtins, and the table says when it is full. */
    fv_vk_image_desc sd = {.format = VK_FORMAT_R32_SFLOAT, .usage = VK_IMAGE_USAGE_STORAGE_BIT, .name = "scratch"};
    fv_image_id id = FV_IMAGE_MAX;
    int made = 0;
    fv_test_log_capture_begin();
    while (fv_images_scratch(&t, &sd, &id) == FV_OK) made++;
    fv_test_log_capture_end();
    assert_int_equal(made, FV_IMAGE_MAX - FV_IMAGE_BUILTIN_COUNT);
    fv_assert_log_contains("the table holds");
    fv_images_fini(&t);
    fv_images_fini(&t); /* safe twice */
    close_vk(&vk);
}

static void compute_helper_refuses_a_bad_description(void **state)
{
    (void)state;
    fv_vk *vk = open_vk();
    static const uint32_t not_spirv[8] = {0};
    fv_vk_compute c;
    fv_vk_compute_desc d = {.name = "bad", .code = not_spirv, .code_size = sizeof not_spirv,
                            .variant_count = FV_VK_COMPUTE_MAX_VARIANTS + 1};
    fv_test_log_capture_begin();
    assert_int_equal(fv_vk_compute_init(vk, &d, &c), FV_ERR_INVALID_ARG);
    d.variant_count = 1;
    assert_true(FV_FAILED(fv_vk_compute_init(vk, &d, &c))); /* not SPIR-V */
    fv_test_log_capture_end();
    fv_assert_log_contains("not SPIR-V");
    fv_vk_compute_fini(vk, &c); /* safe after a failure */
    close_vk(&vk);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_missing_device_extension_makes_every_device_unusable_and_says_which),
        cmocka_unit_test(a_missing_instance_extension_is_refused_before_the_instance),
        cmocka_unit_test(a_failing_surface_callback_fails_the_core_cleanly),
        cmocka_unit_test(image_table_tracks_writes_reads_and_readbacks_without_hazards),
        cmocka_unit_test(compute_helper_refuses_a_bad_description),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
