/* tempfile.c - what seabake writes under a temporary name, and the proof
 * that lets a later run remove what a killed one left (seabake(1), FILES).
 *
 * seabake removes a temporary only when it can show that it made it: never
 * on a name alone.  Every temporary is a directory holding a marker file,
 * SEA_TEMP_MARKER, written by the process that made it: its first line is
 * SEA_TEMP_MAGIC, then "kind KIND" (bake's "tmp" and "old" directories, a
 * file's "file"), "target NAME" (what it becomes) and the process's pid and
 * host.  A directory without the marker, with a marker of another kind or
 * target, or with one another user wrote, is left alone.
 *
 * A file written atomically is a directory PATH.tmp.XXXXXX beside PATH
 * (rename() is atomic only within one file system) holding the marker and
 * the data under PATH's own name, DIR/NAME, renamed onto PATH when
 * complete.  Its maker holds an flock on the directory from before the
 * marker exists until after it is gone, so a directory whose flock another
 * process can take, and whose marker is there, belongs to a process that
 * died (SIGKILL, a power cut, SIGXFSZ before seabake ignored it).  Where the
 * file system has no flock, the cleaner's flock fails as well and the
 * directory is kept.
 *
 * One window stays: a process killed between mkdtemp and the marker's
 * write, or between the marker's removal and rmdir (microseconds, against
 * the milliseconds of the data's write), leaves an empty directory that
 * nothing proves seabake's; it is left alone, as any other. */
#define _GNU_SOURCE /* nftw (XSI) beside flock (BSD) */
#include "config.h"

#include <dirent.h>
#include <ftw.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "internal.h"

static const char SEA_TEMP_MAGIC[] = "seabake temporary directory";
/* What mkdtemp puts after "NAME.tmp.": six letters or digits. */
enum { SEA_TEMP_SUFFIX = 11 }; /* strlen(".tmp.XXXXXX") */

static char *join(const char *dir, const char *name, size_t nlen)
{
    const size_t dlen = strlen(dir);
    char *p = malloc(dlen + nlen + 2);
    if (p != NULL)
        snprintf(p, dlen + nlen + 2, "%s/%.*s", dir, (int)nlen, name);
    return p;
}

/* ------------------------------------------------------------ paths */

char *sea_path_join(const char *dir, const char *name)
{
    return join(dir, name, strlen(name));
}

char *sea_path_parent(const char *path)
{
    size_t len = strlen(path);
    while (len > 1 && path[len - 1] == '/')
        --len;
    while (len > 0 && path[len - 1] != '/')
        --len;
    if (len == 0)
        return strdup(".");
    while (len > 1 && path[len - 1] == '/')
        --len;
    return strndup(path, len);
}

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

int sea_remove_tree(const char *path)
{
    /* FTW_PHYS: a symbolic link inside is removed, never followed */
    return nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

int sea_temp_marker_write(const char *dir, const char *kind, const char *target, size_t tlen)
{
    char *path = join(dir, SEA_TEMP_MARKER, strlen(SEA_TEMP_MARKER));
    if (path == NULL)
        return ENOMEM;
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    int e = 0;
    /* O_EXCL and O_NOFOLLOW: nothing is overwritten or followed. */
    const int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
        e = errno;
    } else {
        const size_t size = tlen + 512;
        char *text = malloc(size);
        int n = text == NULL ? -1
                             : snprintf(text, size, "%s\nkind %s\ntarget %.*s\npid %ld\nhost %s\n",
                                        SEA_TEMP_MAGIC, kind, (int)tlen, target,
                                        (long)getpid(), host);
        if (text == NULL)
            e = ENOMEM;
        else if (n < 0 || (size_t)n >= size || write(fd, text, (size_t)n) != n)
            e = errno ? errno : EIO;
        free(text);
        if (close(fd) != 0 && e == 0)
            e = errno;
        if (e != 0)
            unlink(path);
    }
    free(path);
    return e;
}

int sea_temp_marker_is(const char *dir, const char *kind, const char *target, size_t tlen)
{
    char *path = join(dir, SEA_TEMP_MARKER, strlen(SEA_TEMP_MARKER));
    if (path == NULL)
        return 0;
    const int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    free(path);
    if (fd < 0)
        return 0;
    /* The text the maker wrote before its pid, compared byte for byte (a
     * target may hold any character but '/' and NUL, a newline too). */
    const size_t wlen = sizeof SEA_TEMP_MAGIC + 6 + strlen(kind) + 8 + tlen + 1;
    char *want = malloc(wlen + 1), *got = malloc(wlen + 1);
    struct stat sb;
    int ok = 0;
    if (want != NULL && got != NULL && fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode) &&
        sb.st_uid == geteuid()) {
        const int n = snprintf(want, wlen + 1, "%s\nkind %s\ntarget %.*s\n", SEA_TEMP_MAGIC, kind,
                               (int)tlen, target);
        size_t have = 0;
        ssize_t r = 0;
        while (n > 0 && have < (size_t)n &&
               (r = read(fd, got + have, (size_t)n - have)) > 0)
            have += (size_t)r;
        ok = n > 0 && have == (size_t)n && memcmp(got, want, (size_t)n) == 0;
    }
    free(want);
    free(got);
    close(fd);
    return ok;
}

void sea_temp_marker_remove(const char *dir)
{
    char *path = join(dir, SEA_TEMP_MARKER, strlen(SEA_TEMP_MARKER));
    if (path != NULL)
        unlink(path);
    free(path);
}

/* ------------------------------------------------------------ files */

int sea_temp_open(sea_temp_file *t, const char *path, int *fd)
{
    *t = (sea_temp_file){ NULL, NULL, -1 };
    *fd = -1;
    const char *slash = strrchr(path, '/');
    const char *name = slash != NULL ? slash + 1 : path;
    const size_t plen = strlen(path), nlen = strlen(name);
    if (nlen == 0)
        return EISDIR;
    int e = 0;
    if ((t->dir = malloc(plen + SEA_TEMP_SUFFIX + 1)) == NULL)
        return ENOMEM;
    snprintf(t->dir, plen + SEA_TEMP_SUFFIX + 1, "%s.tmp.XXXXXX", path);
    if (mkdtemp(t->dir) == NULL) {
        e = errno;
        free(t->dir);
        t->dir = NULL;
        return e;
    }
    /* The flock first, then the marker: a cleaner that finds the marker
     * finds the flock taken. */
    t->dir_fd = open(t->dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (t->dir_fd < 0) {
        e = errno;
    } else {
        flock(t->dir_fd, LOCK_EX | LOCK_NB);
        e = sea_temp_marker_write(t->dir, "file", name, nlen);
    }
    if (e == 0 && (t->data = join(t->dir, name, nlen)) == NULL)
        e = ENOMEM;
    /* 0666 less the umask, as any new file (mkstemp would force 0600). */
    if (e == 0 && (*fd = open(t->data, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC,
                              0666)) < 0)
        e = errno;
    if (e != 0) {
        if (*fd < 0) {
            free(t->data); /* not created: nothing to unlink */
            t->data = NULL;
        }
        sea_temp_abort(t);
    }
    return e;
}

void sea_temp_abort(sea_temp_file *t)
{
    if (t->data != NULL)
        unlink(t->data);
    if (t->dir != NULL) {
        sea_temp_marker_remove(t->dir);
        rmdir(t->dir);
    }
    /* the flock goes last, with the directory already gone */
    if (t->dir_fd >= 0)
        close(t->dir_fd);
    free(t->data);
    free(t->dir);
    *t = (sea_temp_file){ NULL, NULL, -1 };
}

int sea_temp_commit(sea_temp_file *t, const char *path)
{
    int e = 0;
    if (t->data == NULL)
        e = EINVAL;
    else if (rename(t->data, path) != 0)
        e = errno;
    else {
        free(t->data);
        t->data = NULL;
    }
    sea_temp_abort(t);
    return e;
}

/* ----------------------------------------------------------- clean-up */

/* name is "TARGET.tmp.XXXXXX" (six letters or digits): TARGET's length, or
 * 0 when it is not. */
static size_t temp_target_len(const char *name)
{
    const size_t len = strlen(name);
    if (len <= SEA_TEMP_SUFFIX || strncmp(name + len - SEA_TEMP_SUFFIX, ".tmp.", 5) != 0)
        return 0;
    for (const char *c = name + len - 6; *c != '\0'; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9')))
            return 0;
    return len - SEA_TEMP_SUFFIX;
}

size_t sea_temp_clean(const char *dir, const char *prefix,
                      void (*removed)(void *ctx, const char *path), void *ctx)
{
    DIR *d = opendir(dir);
    if (d == NULL)
        return 0;
    const size_t plen = strlen(prefix);
    const uid_t me = geteuid();
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const size_t tlen = temp_target_len(e->d_name);
        /* a target that is prefix itself, or prefix then '.' or '_' (the
         * frame number, an AOV's name, the extension) */
        if (tlen < plen || strncmp(e->d_name, prefix, plen) != 0 ||
            (plen > 0 && tlen > plen && e->d_name[plen] != '.' && e->d_name[plen] != '_'))
            continue;
        char *path = join(dir, e->d_name, strlen(e->d_name));
        if (path == NULL)
            break;
        const int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        struct stat sb;
        /* ours, and its maker's flock gone: taken here, held while it goes */
        if (fd >= 0 && fstat(fd, &sb) == 0 && sb.st_uid == me &&
            flock(fd, LOCK_EX | LOCK_NB) == 0 &&
            sea_temp_marker_is(path, "file", e->d_name, tlen)) {
            /* exactly what seabake put there: the data and the marker; a
             * directory that holds anything else stays */
            char *data = join(path, e->d_name, tlen);
            if (data != NULL)
                unlink(data);
            free(data);
            sea_temp_marker_remove(path);
            if (rmdir(path) == 0) {
                n++;
                if (removed != NULL)
                    removed(ctx, path);
            }
        }
        if (fd >= 0)
            close(fd);
        free(path);
    }
    closedir(d);
    return n;
}
