/* files.c - the files and directories of the subcommands: names, writable
 * parents, files written atomically (a temporary name next to the
 * destination, renamed when complete) and output directories (created,
 * their parent must exist).  bake's atomic directory is the library's
 * (sea_bake_dir, src/bake/atomicdir.c). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "internal.h"

/* ------------------------------------------------------------------ names */

/* SEA_ERR_IO unless dir is a directory we can create files in. */
static sea_status writable_dir(const char *opt, const char *dir, sea_error *err)
{
    if (access(dir, W_OK | X_OK) != 0)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot write into directory '%s': %s", opt, dir,
                        strerror(errno));
    return SEA_OK;
}

sea_status sea_cli_check_written(FILE *out, sea_error *err)
{
    if (ferror(out))
        return sea_fail(err, SEA_ERR_IO, "cannot write to standard output");
    return SEA_OK;
}

bool sea_cli_has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n > m && strcasecmp(s + n - m, suffix) == 0;
}

char *sea_cli_path_join(const char *dir, const char *name)
{
    return sea_path_join(dir, name);
}

char *sea_cli_parent_dir(const char *path)
{
    return sea_path_parent(path);
}

/* The one rule for outputs: the output itself is created, its parent
 * directory must exist (nothing is created on the way, so a failure never
 * leaves empty directories behind). */
static sea_status check_dir_exists(const char *opt, const char *dir, sea_error *err)
{
    struct stat sb;
    if (stat(dir, &sb) != 0) {
        if (errno == ENOENT)
            return sea_fail(err, SEA_ERR_IO, "%s: the directory '%s' does not exist", opt, dir);
        return sea_fail(err, SEA_ERR_IO, "%s: cannot examine '%s': %s", opt, dir,
                        strerror(errno));
    }
    if (!S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "%s: '%s' is not a directory", opt, dir);
    return writable_dir(opt, dir, err);
}

sea_status sea_cli_check_parent_writable(const char *opt, const char *path, sea_error *err)
{
    char *dir = sea_cli_parent_dir(path);
    if (dir == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = check_dir_exists(opt, dir, err);
    free(dir);
    return st;
}

/* ------------------------------------------------------------------ files */

sea_status sea_cli_atomic_open(sea_cli_atomic_file *af, const char *opt, const char *path,
                               sea_error *err)
{
    *af = (sea_cli_atomic_file){path, NULL, NULL};
    if ((af->tmp = malloc(sizeof *af->tmp)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    int fd;
    const int e = sea_temp_open(af->tmp, path, &fd);
    if (e != 0) {
        free(af->tmp);
        af->tmp = NULL;
        return sea_fail(err, SEA_ERR_IO, "%s: cannot create a file next to '%s': %s", opt, path,
                        strerror(e));
    }
    if ((af->f = fdopen(fd, "w")) == NULL) {
        const int fe = errno;
        close(fd);
        sea_cli_atomic_abort(af);
        return sea_fail(err, SEA_ERR_IO, "%s: cannot open '%s': %s", opt, path, strerror(fe));
    }
    return SEA_OK;
}

/* Removes the temporary file; nothing is left at the destination. */
void sea_cli_atomic_abort(sea_cli_atomic_file *af)
{
    if (af->f != NULL)
        fclose(af->f);
    if (af->tmp != NULL) {
        sea_temp_abort(af->tmp);
        free(af->tmp);
    }
    af->f = NULL;
    af->tmp = NULL;
}

sea_status sea_cli_atomic_commit(sea_cli_atomic_file *af, const char *opt, sea_error *err)
{
    /* The data reach the disk before the rename, or a crash could leave an
     * empty file under the final name. */
    int e = 0;
    if (fflush(af->f) != 0 || ferror(af->f) || fsync(fileno(af->f)) != 0)
        e = errno ? errno : EIO;
    if (fclose(af->f) != 0 && e == 0)
        e = errno;
    af->f = NULL;
    if (e != 0) {
        sea_cli_atomic_abort(af);
        return sea_fail(err, SEA_ERR_IO, "%s: cannot write '%s': %s", opt, af->path, strerror(e));
    }
    e = sea_temp_commit(af->tmp, af->path);
    free(af->tmp);
    af->tmp = NULL;
    if (e != 0)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot rename the finished file to '%s': %s", opt,
                        af->path, strerror(e));
    return SEA_OK;
}

/* A note for each stale temporary removed, as bake's. */
static void note_removed(void *ctx, const char *path)
{
    const char *who = ctx;
    fprintf(stderr, "%s: removed '%s', left by a %s that was killed\n", who, path, who);
}

size_t sea_cli_clean_stale_files(const char *who, const char *stem)
{
    char *dir = sea_cli_parent_dir(stem);
    const char *slash = strrchr(stem, '/');
    size_t n = 0;
    if (dir != NULL)
        n = sea_temp_clean(dir, slash != NULL ? slash + 1 : stem, note_removed, (void *)who);
    free(dir);
    return n;
}

/* Creates dir (its parent must exist) unless it is there, then checks that
 * it is a writable directory. */
sea_status sea_cli_make_dir(const char *opt, const char *dir, bool *created, sea_error *err)
{
    *created = false;
    if (dir[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "%s: empty directory name", opt);
    struct stat sb;
    if (stat(dir, &sb) != 0) {
        if (errno != ENOENT)
            return sea_fail(err, SEA_ERR_IO, "%s: cannot examine '%s': %s", opt, dir,
                            strerror(errno));
        sea_status st = sea_cli_check_parent_writable(opt, dir, err);
        if (st != SEA_OK)
            return st;
        if (mkdir(dir, 0777) == 0)
            *created = true;
        else if (errno != EEXIST)
            return sea_fail(err, SEA_ERR_IO, "%s: cannot create directory '%s': %s", opt, dir,
                            strerror(errno));
        if (stat(dir, &sb) != 0)
            return sea_fail(err, SEA_ERR_IO, "%s: cannot examine '%s': %s", opt, dir,
                            strerror(errno));
    }
    if (!S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "%s: '%s' is not a directory", opt, dir);
    return writable_dir(opt, dir, err);
}
