/* @brief Every repository path to a scene or HMD profile file that README.md and the docs/ pages name (scenes/...json,
 * hmd/...json, as a user would type them from the checkout's root) exists (issue 28 item 6: docs/scene-file.md named
 * scenes/bunny-in-box.scene.json, the file is bunny-in-the-box). A path inside another one (../shared/data/scenes/...)
 * is not a repository path and is left out; so is an upper-case placeholder (hmd/NAME.json). */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <stdbool.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fv_test.h"

static bool path_char(char c) { return isalnum((unsigned char)c) || c == '_' || c == '.' || c == '-'; }

static bool placeholder(const char *name, size_t len)
{
    for (size_t i = 0; i + 5 < len; i++)
        if (!isupper((unsigned char)name[i])) return false;
    return true;
}

/* Check every path in the document at `full` (shown as `rel`); returns how many it named, counts the missing ones
 * in *missing. */
static int check_document(const char *full, const char *rel, int *missing)
{
    size_t len = 0;
    char *text = fv_test_read_file(full, &len);
    int named = 0, line = 1;
    static const char *const dirs[] = {"scenes/", "hmd/"};
    for (size_t i = 0; i < len; i++) {
        if (text[i] == '\n') line++;
        if (i > 0 && (path_char(text[i - 1]) || text[i - 1] == '/')) continue;
        for (int d = 0; d < 2; d++) {
            size_t dl = strlen(dirs[d]);
            if (strncmp(text + i, dirs[d], dl) != 0) continue;
            size_t e = i + dl;
            while (e < len && path_char(text[e])) e++;
            size_t nlen = e - (i + dl);
            if (nlen < 6 || strncmp(text + e - 5, ".json", 5) != 0 || placeholder(text + i + dl, nlen)) continue;
            char path[4096];
            snprintf(path, sizeof path, "%s/%.*s", FV_SOURCE_DIR, (int)(e - i), text + i);
            named++;
            if (access(path, R_OK) != 0) {
                print_error("%s:%d names %.*s, which does not exist\n", rel, line, (int)(e - i), text + i);
                (*missing)++;
            }
        }
    }
    free(text);
    return named;
}

static void every_scene_and_hmd_path_in_the_docs_exists(void **state)
{
    (void)state;
    int missing = 0, named = check_document(FV_SOURCE_DIR "/README.md", "README.md", &missing);
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/docs", FV_SOURCE_DIR);
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t n = strlen(e->d_name);
        if (n < 4 || strcmp(e->d_name + n - 3, ".md") != 0) continue;
        char full[4096], rel[512];
        snprintf(full, sizeof full, "%s/docs/%s", FV_SOURCE_DIR, e->d_name);
        snprintf(rel, sizeof rel, "docs/%s", e->d_name);
        named += check_document(full, rel, &missing);
    }
    closedir(d);
    print_message("%d scene and HMD paths named in README.md and docs/*.md, %d missing\n", named, missing);
    assert_true(named >= 3); /* the scan sees the paths it is meant to check */
    assert_int_equal(missing, 0);
}

/* The scan itself: a document with a missing path, a nested path and a placeholder. */
static void the_scan_finds_a_missing_path(void **state)
{
    (void)state;
    const char *doc = "fovea run --scene scenes/no-such.scene.json\n"
                      "see ../shared/data/scenes/x.json and hmd/NAME.json, or hmd/generic.json\n";
    const char *tmp = fv_test_write_file("docs_paths_probe.md", doc, strlen(doc));
    int missing = 0, named = check_document(tmp, "probe.md", &missing);
    assert_int_equal(named, 2);
    assert_int_equal(missing, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_scene_and_hmd_path_in_the_docs_exists),
        cmocka_unit_test(the_scan_finds_a_missing_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
