/* fuzz_common.h - what the libFuzzer targets of tests/fuzz/ share: the
 * library reads its inputs from files, so each input is written to a file
 * in a private temporary directory (made once per process, removed at
 * exit) and loaded from there. */
#ifndef SEABAKE_FUZZ_COMMON_H
#define SEABAKE_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "seabake.h"

static char fuzz_dir[64];

static void fuzz_cleanup(void)
{
    char cmd[128];
    if (fuzz_dir[0]) {
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", fuzz_dir);
        if (system(cmd) != 0)
            fprintf(stderr, "fuzz: could not remove %s\n", fuzz_dir);
    }
}

/* The private directory, made on first use. */
static const char *fuzz_tmpdir(void)
{
    if (!fuzz_dir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(fuzz_dir, sizeof fuzz_dir, "%s/seabake-fuzz.XXXXXX",
                 base && base[0] && strlen(base) < 32 ? base : "/tmp");
        if (!mkdtemp(fuzz_dir)) {
            perror("fuzz: mkdtemp");
            abort();
        }
        atexit(fuzz_cleanup);
        sea_init();
    }
    return fuzz_dir;
}

/* Writes size bytes to dir/name and returns the path (static storage, one
 * per name slot). */
__attribute__((unused)) static const char *fuzz_write(const char *name, const uint8_t *data, size_t size, char *path,
                              size_t path_size)
{
    snprintf(path, path_size, "%s/%s", fuzz_tmpdir(), name);
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        perror("fuzz: writing the input");
        abort();
    }
    return path;
}

/* Crashes (a finding) when cond is false: an invariant the API promises. */
#define FUZZ_ASSERT(cond)                                                                      \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            fprintf(stderr, "fuzz: %s:%d: invariant failed: %s\n", __FILE__, __LINE__, #cond); \
            abort();                                                                           \
        }                                                                                      \
    } while (0)

/* An error message is one non-empty line, NUL-terminated inside the buffer. */
static void fuzz_check_error(sea_status st, const sea_error *err)
{
    if (st == SEA_OK)
        return;
    FUZZ_ASSERT(memchr(err->msg, '\0', sizeof err->msg) != NULL);
    FUZZ_ASSERT(err->msg[0] != '\0');
}

#endif
