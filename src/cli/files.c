/* files.c - the files and directories of the subcommands: names, writable
 * parents, files written atomically (a temporary name next to the
 * destination, renamed when complete), output directories created with
 * their parents, and bake's atomic directories (a sibling DIR.tmp.XXXXXX
 * renamed over DIR when every file is in it). */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"

/* ------------------------------------------------------------------ names */

/* SEA_ERR_IO unless dir is a directory we can create files in. */
static sea_status writable_dir(const char *opt, const char *dir, sea_error *err)
{
    if (access(dir, W_OK | X_OK) != 0)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot write into directory '%s': %s", opt, dir,
                        strerror(errno));
    return SEA_OK;
}

mode_t sea_cli_umask(void)
{
    const mode_t mask = umask(0);
    umask(mask);
    return mask;
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
    const size_t len = strlen(dir) + strlen(name) + 2;
    char *p = malloc(len);
    if (p != NULL)
        snprintf(p, len, "%s/%s", dir, name);
    return p;
}

sea_status sea_cli_check_parent_writable(const char *opt, const char *path, sea_error *err)
{
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
    if (dir == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = writable_dir(opt, dir, err);
    free(dir);
    return st;
}

/* ------------------------------------------------------------------ files */

sea_status sea_cli_atomic_open(sea_cli_atomic_file *af, const char *opt, const char *path,
                               sea_error *err)
{
    *af = (sea_cli_atomic_file){path, NULL, NULL};
    af->tmp = sea_cli_sibling_template(path, "tmp");
    if (af->tmp == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    int fd = mkstemp(af->tmp);
    if (fd < 0) {
        int e = errno;
        free(af->tmp);
        af->tmp = NULL;
        return sea_fail(err, SEA_ERR_IO, "%s: cannot create a file next to '%s': %s", opt, path,
                        strerror(e));
    }
    /* mkstemp creates mode 0600; a new output file gets 0666 less the umask. */
    if (fchmod(fd, 0666 & ~sea_cli_umask()) != 0 || (af->f = fdopen(fd, "w")) == NULL) {
        int e = errno;
        close(fd);
        unlink(af->tmp);
        free(af->tmp);
        af->tmp = NULL;
        return sea_fail(err, SEA_ERR_IO, "%s: cannot open '%s': %s", opt, path, strerror(e));
    }
    return SEA_OK;
}

/* Removes the temporary file; nothing is left at the destination. */
void sea_cli_atomic_abort(sea_cli_atomic_file *af)
{
    if (af->f != NULL)
        fclose(af->f);
    if (af->tmp != NULL) {
        unlink(af->tmp);
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
    if (rename(af->tmp, af->path) != 0) {
        e = errno;
        sea_cli_atomic_abort(af);
        return sea_fail(err, SEA_ERR_IO, "%s: cannot rename the finished file to '%s': %s", opt,
                        af->path, strerror(e));
    }
    free(af->tmp);
    af->tmp = NULL;
    return SEA_OK;
}

/* mkdir -p dir, then checks that it is a writable directory. */
sea_status sea_cli_make_dir(const char *opt, const char *dir, sea_error *err)
{
    if (dir[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "%s: empty directory name", opt);
    char *p = strdup(dir);
    if (p == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    for (char *s = p + 1; *s; ++s) {
        if (*s != '/')
            continue;
        *s = '\0';
        if (mkdir(p, 0777) != 0 && errno != EEXIST) {
            int e = errno;
            sea_status st = sea_fail(err, SEA_ERR_IO, "%s: cannot create directory '%s': %s", opt,
                                     p, strerror(e));
            free(p);
            return st;
        }
        *s = '/';
    }
    free(p);
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return sea_fail(err, SEA_ERR_IO, "%s: cannot create directory '%s': %s", opt, dir,
                        strerror(errno));
    struct stat sb;
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "%s: '%s' is not a directory", opt, dir);
    return writable_dir(opt, dir, err);
}

/* ------------------------------------------------------------ directories */

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

/* Removes a directory tree we created; best effort (used on failure paths
 * and for the old DIR after the new one is in place). */
int sea_cli_remove_tree(const char *path)
{
    return nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* "DIR.<what>.XXXXXX", malloc'ed. */
char *sea_cli_sibling_template(const char *dir, const char *what)
{
    const size_t len = strlen(dir) + strlen(what) + 10;
    char *p = malloc(len);
    if (p != NULL)
        snprintf(p, len, "%s.%s.XXXXXX", dir, what);
    return p;
}

/* DIR must be absent or a directory. */
sea_status sea_cli_check_dir(const char *dir, sea_error *err)
{
    struct stat sb;
    if (lstat(dir, &sb) != 0) {
        if (errno == ENOENT)
            return SEA_OK;
        return sea_fail(err, SEA_ERR_IO, "-o: cannot examine '%s': %s", dir, strerror(errno));
    }
    if (!S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_DOMAIN, "-o: '%s' exists and is not a directory", dir);
    return SEA_OK;
}

/* Puts the finished temporary directory in place of dir. */
sea_status sea_cli_commit_dir(const char *tmp, const char *dir, sea_error *err)
{
    struct stat sb;
    if (lstat(dir, &sb) != 0) {
        if (rename(tmp, dir) != 0)
            return sea_fail(err, SEA_ERR_IO, "-o: cannot rename '%s' to '%s': %s", tmp, dir,
                            strerror(errno));
        return SEA_OK;
    }
    if (!S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_DOMAIN, "-o: '%s' exists and is not a directory", dir);
    char *old = sea_cli_sibling_template(dir, "old");
    if (old == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    /* mkdtemp reserves a unique name; renaming a directory onto an empty
     * directory replaces it (POSIX rename). */
    if (mkdtemp(old) == NULL) {
        sea_status st = sea_fail(err, SEA_ERR_IO, "-o: cannot create '%s': %s", old,
                                 strerror(errno));
        free(old);
        return st;
    }
    if (rename(dir, old) != 0) {
        sea_status st = sea_fail(err, SEA_ERR_IO, "-o: cannot move '%s' aside to '%s': %s", dir,
                                 old, strerror(errno));
        rmdir(old);
        free(old);
        return st;
    }
    if (rename(tmp, dir) != 0) {
        sea_status st = sea_fail(err, SEA_ERR_IO, "-o: cannot rename '%s' to '%s': %s", tmp, dir,
                                 strerror(errno));
        rename(old, dir); /* put the old one back */
        free(old);
        return st;
    }
    sea_cli_remove_tree(old);
    free(old);
    return SEA_OK;
}
