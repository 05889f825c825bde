/* blender.c - the Blender import script (blender.h): its text, compiled in
 * from exporters/blender/seabake_import.py (blender_py.c), and a copy of it
 * written beside a manifest. */
#include "config.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "blender.h"
#include "internal.h"

const char *sea_blender_script(void)
{
    return sea_blender_import_text;
}

sea_status sea_blender_write_script(const char *dir, sea_error *err)
{
    char *path = sea_path_join(dir, SEA_BLENDER_SCRIPT);
    if (path == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_temp_file tmp;
    int fd = -1;
    int e = sea_temp_open(&tmp, path, &fd);
    if (e != 0) {
        sea_status st = sea_fail(err, e == ENOMEM ? SEA_ERR_NOMEM : SEA_ERR_IO,
                                 "cannot create '%s': %s", path, strerror(e));
        free(path);
        return st;
    }
    const char *text = sea_blender_import_text;
    size_t left = strlen(text);
    while (e == 0 && left > 0) {
        const ssize_t k = write(fd, text, left);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            e = k < 0 ? errno : EIO;
        else {
            text += k;
            left -= (size_t)k;
        }
    }
    /* the data on disk before the rename, as the maps' */
    if (e == 0 && fsync(fd) != 0)
        e = errno;
    if (close(fd) != 0 && e == 0)
        e = errno;
    if (e == 0)
        e = sea_temp_commit(&tmp, path);
    else
        sea_temp_abort(&tmp);
    sea_status st = e == 0 ? SEA_OK
                           : sea_fail(err, SEA_ERR_IO, "cannot write '%s': %s", path, strerror(e));
    free(path);
    return st;
}
