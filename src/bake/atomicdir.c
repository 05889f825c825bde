/* atomicdir.c - the atomic bake directory (bakedir.h, sea_bake_dir): a
 * sibling DIR.tmp.XXXXXX that the files go into, renamed over DIR when
 * every file is in it, under a lock beside DIR.
 *
 * What seabake may remove or replace.  seabake removes or replaces a
 * directory only when it can show that it wrote it: never on a name alone.
 * Its temporaries (DIR.tmp.XXXXXX while a bake runs, DIR.old.XXXXXX inside
 * a commit, FILE.tmp.XXXXXX while a file is written) hold a marker file,
 * SEA_TEMP_MARKER, written by the process that made them (tempfile.c):
 * "kind tmp", "kind old" or "kind file", "target BASE" (the directory or
 * file it belongs to), and the process's pid and host.  A directory named
 * like a temporary without that marker, or whose marker names another kind
 * or target, or that another user owns, is left alone.
 *
 * A bake directory that may be replaced is empty, or holds a manifest.json
 * with "format": "seabake-bake" whose "files" list names every other entry,
 * each a regular file (the marker of an interrupted commit aside). */
#define _GNU_SOURCE /* renameat2 */
#include "config.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "bakedir.h"
#include "internal.h"

struct sea_bake_dir {
    char *user;   /* the path as given, without trailing slashes */
    char *target; /* the directory replaced (a link's target, resolved) */
    char *parent; /* its parent directory */
    char *lock;   /* PARENT/.BASE.lock */
    char *tmp;    /* the temporary directory, NULL once committed */
    int lock_fd, tmp_fd;
    int made;     /* tmp was created by this bake */
    /* the hooks, opt as the prefix of messages ("-o: ") and the name of
     * what to choose instead ("-o", or "directory") */
    char pre[64], choose[64];
    sea_bake_note_fn note;
    sea_progress_fn progress;
    void *ctx;
};

static void note(const sea_bake_dir *d, sea_bake_note kind, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void note(const sea_bake_dir *d, sea_bake_note kind, const char *fmt, ...)
{
    if (d->note == NULL)
        return;
    char text[SEA_ERROR_MSG_MAX + 256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    d->note(d->ctx, kind, text);
}

/* The process's umask, read without changing it for long: a new directory
 * gets 0777 less it. */
static mode_t current_umask(void)
{
    const mode_t mask = umask(0);
    umask(mask);
    return mask;
}

/* The one rule for outputs: the output itself is created, its parent
 * directory must exist and be writable (nothing is created on the way, so
 * a failure never leaves empty directories behind). */
static sea_status check_dir_exists(const sea_bake_dir *d, const char *dir, sea_error *err)
{
    struct stat sb;
    if (stat(dir, &sb) != 0) {
        if (errno == ENOENT)
            return sea_fail(err, SEA_ERR_IO, "%sthe directory '%s' does not exist", d->pre, dir);
        return sea_fail(err, SEA_ERR_IO, "%scannot examine '%s': %s", d->pre, dir,
                        strerror(errno));
    }
    if (!S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "%s'%s' is not a directory", d->pre, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return sea_fail(err, SEA_ERR_IO, "%scannot write into directory '%s': %s", d->pre, dir,
                        strerror(errno));
    return SEA_OK;
}

/* "DIR.<what>.XXXXXX", malloc'ed. */
static char *sibling_template(const char *dir, const char *what)
{
    const size_t len = strlen(dir) + strlen(what) + 10;
    char *p = malloc(len);
    if (p != NULL)
        snprintf(p, len, "%s.%s.XXXXXX", dir, what);
    return p;
}

/* The last component of path (no trailing slash), pointing into path. */
static const char *base_name(const char *path, size_t *len)
{
    size_t end = strlen(path);
    while (end > 1 && path[end - 1] == '/')
        --end;
    size_t start = end;
    while (start > 0 && path[start - 1] != '/')
        --start;
    *len = end - start;
    return path + start;
}

/* ------------------------------------------------------------------ lock */

/* Takes the lock beside the directory, waiting for another bake's commit
 * (with a note). */
static sea_status take_lock(sea_bake_dir *d, sea_error *err)
{
    if (d->lock_fd < 0) {
        /* O_NOFOLLOW: a symbolic link planted under the lock's name must
         * not make the bake create or lock a file elsewhere. */
        d->lock_fd = open(d->lock, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);
        /* another user's lock file: flock needs no write access */
        if (d->lock_fd < 0 && errno == EACCES)
            d->lock_fd = open(d->lock, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
        if (d->lock_fd < 0 && errno == ELOOP)
            return sea_fail(err, SEA_ERR_IO,
                            "%sthe lock file '%s' is a symbolic link; remove it (seabake makes "
                            "it as an empty file)",
                            d->pre, d->lock);
        if (d->lock_fd < 0)
            return sea_fail(err, SEA_ERR_IO, "%scannot create the lock file '%s': %s", d->pre,
                            d->lock, strerror(errno));
        struct stat sb;
        if (fstat(d->lock_fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
            close(d->lock_fd);
            d->lock_fd = -1;
            return sea_fail(err, SEA_ERR_IO,
                            "%sthe lock file '%s' is not a regular file; remove it (seabake "
                            "makes it as an empty file)",
                            d->pre, d->lock);
        }
    }
    if (flock(d->lock_fd, LOCK_EX | LOCK_NB) == 0)
        return SEA_OK;
    if (errno != EWOULDBLOCK)
        return SEA_OK; /* no flock on this file system: unlocked, as before */
    note(d, SEA_BAKE_NOTE_WAITING, "waiting for another bake to finish writing '%s'", d->user);
    /* a signal interrupts the wait (EINTR) and the caller decides */
    while (flock(d->lock_fd, LOCK_EX) != 0) {
        if (errno != EINTR || (d->progress != NULL && d->progress(d->ctx, 0.0) != 0))
            return sea_fail(err, SEA_ERR_IO, "%scannot lock '%s': %s", d->pre, d->lock,
                            strerror(errno));
    }
    return SEA_OK;
}

static void drop_lock(sea_bake_dir *d)
{
    if (d->lock_fd >= 0) {
        flock(d->lock_fd, LOCK_UN);
        close(d->lock_fd);
        d->lock_fd = -1;
    }
}

/* ---------------------------------------------- what may be replaced */

/* A manifest is a few hundred kilobytes at most (a thousand frames of six
 * levels); anything far larger is not one of seabake's. */
static const long SEA_MANIFEST_MAX = 64L << 20;

/* "BASE.tmp.XXXXXX" (1) or "BASE.old.XXXXXX" (2), six letters or digits
 * as mkdtemp and move_aside make them; 0 otherwise.  A candidate only: the
 * marker decides. */
static int temporary_kind(const char *name, const char *base, size_t blen)
{
    if (strncmp(name, base, blen) != 0)
        return 0;
    const char *rest = name + blen;
    int kind = strncmp(rest, ".tmp.", 5) == 0 ? 1 : strncmp(rest, ".old.", 5) == 0 ? 2 : 0;
    if (kind == 0 || strlen(rest + 5) != 6)
        return 0;
    for (const char *c = rest + 5; *c; ++c)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9')))
            return 0;
    return kind;
}

/* Reads dir/manifest.json into a cJSON tree; NULL (with *why set) if it is
 * not a regular file of sensible size or not JSON. */
static cJSON *read_manifest(const char *dir, const char **why)
{
    char *path = sea_path_join(dir, "manifest.json");
    if (path == NULL) {
        *why = "out of memory";
        return NULL;
    }
    const int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    free(path);
    struct stat sb;
    char *text = NULL;
    cJSON *m = NULL;
    *why = "its manifest.json cannot be read";
    if (fd >= 0 && fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size <= SEA_MANIFEST_MAX &&
        (text = malloc((size_t)sb.st_size + 1)) != NULL) {
        size_t got = 0;
        ssize_t n;
        while (got < (size_t)sb.st_size &&
               (n = read(fd, text + got, (size_t)sb.st_size - got)) > 0)
            got += (size_t)n;
        text[got] = '\0';
        if (got == (size_t)sb.st_size && (m = cJSON_Parse(text)) == NULL)
            *why = "its manifest.json is not JSON";
    }
    if (fd >= 0)
        close(fd);
    free(text);
    return m;
}

/* True if the manifest's "files" list names name. */
static int manifest_lists(const cJSON *files, const char *name)
{
    const cJSON *f;
    cJSON_ArrayForEach(f, files)
    {
        if (cJSON_IsString(f) && strcmp(f->valuestring, name) == 0)
            return 1;
    }
    return 0;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* SEA_OK if the existing directory d->target may be replaced by a bake
 * (the rule above); otherwise SEA_ERR_DOMAIN naming what was found and how
 * to proceed.  Nothing is changed. */
static sea_status check_replaceable(const sea_bake_dir *d, sea_error *err)
{
    DIR *dir = opendir(d->target);
    if (dir == NULL)
        return sea_fail(err, SEA_ERR_IO, "%scannot read the directory '%s': %s", d->pre, d->user,
                        strerror(errno));
    /* the entries, sorted, so that the message is the same on every run */
    char **names = NULL;
    size_t n = 0, cap = 0;
    int has_manifest = 0, nomem = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0 ||
            strcmp(e->d_name, SEA_TEMP_MARKER) == 0)
            continue;
        if (strcmp(e->d_name, "manifest.json") == 0) {
            has_manifest = 1;
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 16;
            char **more = realloc(names, cap * sizeof *names);
            if (more == NULL) {
                nomem = 1;
                break;
            }
            names = more;
        }
        if ((names[n] = strdup(e->d_name)) == NULL) {
            nomem = 1;
            break;
        }
        ++n;
    }
    closedir(dir);
    sea_status st = SEA_OK;
    cJSON *m = NULL;
    const char *why = NULL;
    char *bad = NULL;
    if (nomem) {
        st = sea_fail(err, SEA_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (n > 1) /* (qsort takes no NULL, even for no elements) */
        qsort(names, n, sizeof *names, compare_names);
    size_t nbad = 0; /* entries the manifest does not account for */
    if (!has_manifest) {
        if (n == 0)
            goto done; /* empty: nothing to lose */
        why = "it has no manifest.json and holds";
        bad = names[0];
        nbad = n;
    } else if ((m = read_manifest(d->target, &why)) != NULL) {
        const cJSON *format = cJSON_GetObjectItemCaseSensitive(m, "format");
        const cJSON *files = cJSON_GetObjectItemCaseSensitive(m, "files");
        why = NULL;
        if (!cJSON_IsString(format) || strcmp(format->valuestring, "seabake-bake") != 0)
            why = "its manifest.json is not a seabake bake's (no \"format\": \"seabake-bake\")";
        else if (!cJSON_IsArray(files))
            why = "its manifest.json has no \"files\" list (a bake by seabake 0.1, or not "
                  "seabake's)";
        for (size_t i = 0; why == NULL && i < n; ++i) {
            struct stat sb;
            char *path = sea_path_join(d->target, names[i]);
            const int regular = path != NULL && lstat(path, &sb) == 0 && S_ISREG(sb.st_mode);
            free(path);
            if (manifest_lists(files, names[i]) && regular)
                continue;
            if (bad == NULL)
                bad = names[i];
            ++nbad;
        }
        if (why == NULL && bad != NULL)
            why = "it holds what its manifest.json does not list as a file of the bake:";
    }
    if (why != NULL) {
        char more[64] = "";
        if (nbad > 1)
            snprintf(more, sizeof more, " and %zu more", nbad - 1);
        if (bad != NULL)
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "%s'%s' is not a bake that seabake wrote (%s '%s'%s); seabake "
                          "replaces only its own bakes: choose another %s, or move or remove "
                          "'%s' yourself",
                          d->pre, d->user, why, bad, more, d->choose, d->user);
        else
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "%s'%s' is not a bake that seabake wrote (%s); seabake replaces only "
                          "its own bakes: choose another %s, or move or remove '%s' yourself",
                          d->pre, d->user, why, d->choose, d->user);
    }
done:
    cJSON_Delete(m);
    for (size_t i = 0; i < n; ++i)
        free(names[i]);
    free(names);
    return st;
}

/* Under the lock: the temporary directories of bakes that are gone.  A live
 * bake holds an flock on its DIR.tmp.XXXXXX from its creation (under this
 * lock) to its end, so one whose flock can be taken is stale; a
 * DIR.old.XXXXXX exists only inside a commit, which holds this lock, so any
 * is stale.  A bake killed between moving DIR aside and putting the new one
 * in place left DIR missing: its old copy is put back.  Each only with
 * seabake's marker inside (above). */
static void clean_stale(const sea_bake_dir *d)
{
    DIR *dir = opendir(d->parent);
    if (dir == NULL)
        return;
    size_t blen;
    const char *base = base_name(d->target, &blen);
    char *b = strndup(base, blen);
    const uid_t me = geteuid();
    struct dirent *e;
    while (b != NULL && (e = readdir(dir)) != NULL) {
        const int kind = temporary_kind(e->d_name, b, blen);
        if (kind == 0)
            continue;
        char *path = sea_path_join(d->parent, e->d_name);
        struct stat sb;
        if (path == NULL || lstat(path, &sb) != 0 || !S_ISDIR(sb.st_mode) || sb.st_uid != me ||
            !sea_temp_marker_is(path, kind == 1 ? "tmp" : "old", b, blen)) {
            free(path);
            continue;
        }
        int stale = kind == 2;
        if (kind == 1) {
            const int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
            stale = fd >= 0 && flock(fd, LOCK_EX | LOCK_NB) == 0;
            if (fd >= 0)
                close(fd);
        }
        if (!stale) {
            free(path);
            continue;
        }
        struct stat tb;
        if (kind == 2 && lstat(d->target, &tb) != 0 && errno == ENOENT &&
            rename(path, d->target) == 0) {
            sea_temp_marker_remove(d->target);
            note(d, SEA_BAKE_NOTE_RESTORED,
                 "'%s' restored from '%s', left by a bake that was killed while replacing it",
                 d->user, e->d_name);
        } else if (sea_remove_tree(path) == 0) {
            note(d, SEA_BAKE_NOTE_REMOVED, "removed '%s', left by a bake that was killed", path);
        }
        free(path);
    }
    free(b);
    closedir(dir);
}

/* Moves the existing target aside to a fresh DIR.old.XXXXXX; *old gets its
 * name.  renameat2's RENAME_NOREPLACE makes the name without a directory
 * to rename onto; where the file system lacks it, mkdtemp reserves the name
 * and rename replaces that empty directory (POSIX). */
static sea_status move_aside(const sea_bake_dir *d, char **old, sea_error *err)
{
    if ((*old = sibling_template(d->target, "old")) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    static const char letters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    char *x = *old + strlen(*old) - 6;
    for (int attempt = 0; attempt < 100; ++attempt) {
        unsigned char r[6];
        if (getrandom(r, sizeof r, 0) != (ssize_t)sizeof r)
            break;
        for (int i = 0; i < 6; ++i)
            x[i] = letters[r[i] % (sizeof letters - 1)];
        if (renameat2(AT_FDCWD, d->target, AT_FDCWD, *old, RENAME_NOREPLACE) == 0)
            return SEA_OK;
        if (errno != EEXIST)
            break;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != EEXIST)
        return sea_fail(err, SEA_ERR_IO, "%scannot move '%s' aside: %s", d->pre, d->target,
                        strerror(errno));
    memcpy(x, "XXXXXX", 6);
    if (mkdtemp(*old) == NULL)
        return sea_fail(err, SEA_ERR_IO, "%scannot create a directory in '%s': %s", d->pre,
                        d->parent, strerror(errno));
    if (rename(d->target, *old) != 0) {
        const int e = errno;
        rmdir(*old);
        return sea_fail(err, SEA_ERR_IO, "%scannot move '%s' aside to '%s': %s", d->pre,
                        d->target, *old, strerror(e));
    }
    return SEA_OK;
}

/* ------------------------------------------------------------- the calls */

/* Checks the path and makes the temporary directory (sea_bake_dir_begin
 * but for the allocation and the clean-up of a failure). */
static sea_status begin(sea_bake_dir *d, const char *dir, sea_error *err)
{
    size_t blen;
    const char *base = base_name(dir, &blen);
    if (dir[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "%sempty directory name", d->pre);
    if (blen == 0 || (blen == 1 && base[0] == '.') || (blen == 2 && strncmp(base, "..", 2) == 0))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "%s'%s' cannot be replaced by the bake (name the directory itself, "
                        "not '.', '..' or '/')",
                        d->pre, dir);
    if ((d->user = strndup(dir, (size_t)(base - dir) + blen)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    /* A symbolic link to a directory: the bake replaces the directory it
     * points to (built beside it, on its file system), the link stays. */
    struct stat sb;
    if (lstat(d->user, &sb) == 0 && S_ISLNK(sb.st_mode)) {
        struct stat tb;
        if (stat(d->user, &tb) != 0)
            return sea_fail(err, SEA_ERR_DOMAIN, "%s'%s' is a symbolic link to nothing (%s)",
                            d->pre, d->user, strerror(errno));
        if (!S_ISDIR(tb.st_mode))
            return sea_fail(err, SEA_ERR_IO, "%s'%s' exists and is not a directory", d->pre,
                            d->user);
        d->target = realpath(d->user, NULL);
        if (d->target == NULL)
            return sea_fail(err, SEA_ERR_IO, "%scannot resolve '%s': %s", d->pre, d->user,
                            strerror(errno));
        if (strcmp(d->target, "/") == 0)
            return sea_fail(err, SEA_ERR_DOMAIN, "%s'%s' points to '/', which cannot be replaced",
                            d->pre, d->user);
    } else if ((d->target = strdup(d->user)) == NULL) {
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    if ((d->parent = sea_path_parent(d->target)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = check_dir_exists(d, d->parent, err);
    if (st != SEA_OK)
        return st;
    base = base_name(d->target, &blen);
    const size_t llen = strlen(d->parent) + blen + 8;
    if ((d->lock = malloc(llen)) == NULL || (d->tmp = sibling_template(d->target, "tmp")) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    snprintf(d->lock, llen, "%s/.%.*s.lock", d->parent, (int)blen, base);

    /* A file where the directory should be is refused before the lock file
     * is made (which would stay behind); under the lock it is checked again. */
    if (lstat(d->target, &sb) == 0 && !S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "%s'%s' exists and is not a directory", d->pre, d->user);
    if ((st = take_lock(d, err)) != SEA_OK)
        return st;
    clean_stale(d);
    if (lstat(d->target, &sb) == 0) {
        struct stat pb;
        if (!S_ISDIR(sb.st_mode))
            st = sea_fail(err, SEA_ERR_IO, "%s'%s' exists and is not a directory", d->pre,
                          d->user);
        else if (stat(d->parent, &pb) == 0 && pb.st_dev != sb.st_dev)
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "%s'%s' is a mount point, which cannot be replaced (bake into a "
                          "directory inside it)",
                          d->pre, d->user);
        else
            st = check_replaceable(d, err);
    } else if (errno != ENOENT) {
        st = sea_fail(err, SEA_ERR_IO, "%scannot examine '%s': %s", d->pre, d->user,
                      strerror(errno));
    }
    if (st == SEA_OK && mkdtemp(d->tmp) == NULL) {
        st = sea_fail(err, SEA_ERR_IO, "%scannot create a directory in '%s': %s", d->pre,
                      d->parent, strerror(errno));
        free(d->tmp);
        d->tmp = NULL;
    }
    d->made = st == SEA_OK;
    if (st == SEA_OK) {
        const int e = sea_temp_marker_write(d->tmp, "tmp", base, blen);
        if (e != 0)
            st = sea_fail(err, SEA_ERR_IO, "%scannot write into '%s': %s", d->pre, d->tmp,
                          strerror(e));
    }
    if (st == SEA_OK) {
        /* The flock that tells other bakes this temporary is alive.  Where
         * the file system has no flock, theirs fails too and they keep it. */
        d->tmp_fd = open(d->tmp, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (d->tmp_fd >= 0)
            flock(d->tmp_fd, LOCK_EX | LOCK_NB);
        /* mkdtemp makes it 0700; DIR gets the umask's permissions */
        if (chmod(d->tmp, 0777 & ~current_umask()) != 0)
            st = sea_fail(err, SEA_ERR_IO, "%scannot set the permissions of '%s': %s", d->pre,
                          d->tmp, strerror(errno));
    }
    drop_lock(d);
    return st;
}

sea_status sea_bake_dir_begin(const char *path, const sea_bake_dir_hooks *hooks,
                              sea_bake_dir **out, sea_error *err)
{
    *out = NULL;
    sea_bake_dir *d = calloc(1, sizeof *d);
    if (d == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    d->lock_fd = d->tmp_fd = -1;
    const char *opt = hooks != NULL ? hooks->opt : NULL;
    if (opt != NULL) {
        snprintf(d->pre, sizeof d->pre, "%s: ", opt);
        snprintf(d->choose, sizeof d->choose, "%s", opt);
    } else {
        snprintf(d->choose, sizeof d->choose, "directory");
    }
    if (hooks != NULL) {
        d->note = hooks->note;
        d->progress = hooks->progress;
        d->ctx = hooks->ctx;
    }
    const sea_status st = begin(d, path, err);
    if (st != SEA_OK) {
        sea_bake_dir_free(d);
        return st;
    }
    *out = d;
    return SEA_OK;
}

const char *sea_bake_dir_path(const sea_bake_dir *d)
{
    return d->tmp;
}

/* Puts the finished temporary directory in place of the target, under the
 * lock: an existing directory, checked again to be a bake, is marked and
 * renamed aside, the new one renamed in, the old one removed, all before
 * another bake may commit. */
sea_status sea_bake_dir_commit(sea_bake_dir *d, sea_error *err)
{
    if (d->tmp == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "the bake directory '%s' is already committed",
                        d->user);
    sea_status st = take_lock(d, err);
    if (st != SEA_OK)
        return st;
    size_t blen;
    const char *base = base_name(d->target, &blen);
    struct stat sb;
    char *old = NULL;
    if (lstat(d->target, &sb) != 0) {
        if (rename(d->tmp, d->target) != 0)
            st = sea_fail(err, SEA_ERR_IO, "%scannot rename '%s' to '%s': %s", d->pre, d->tmp,
                          d->target, strerror(errno));
        else
            sea_temp_marker_remove(d->target);
    } else if (!S_ISDIR(sb.st_mode)) {
        st = sea_fail(err, SEA_ERR_IO, "%s'%s' exists and is not a directory", d->pre, d->user);
    } else if ((st = check_replaceable(d, err)) != SEA_OK) {
        /* something was put into DIR while the bake ran */
    } else {
        /* A marker left by a commit killed before its rename is replaced. */
        sea_temp_marker_remove(d->target);
        int e = sea_temp_marker_write(d->target, "old", base, blen);
        if (e != 0)
            st = sea_fail(err, SEA_ERR_IO, "%scannot write into '%s': %s", d->pre, d->user,
                          strerror(e));
        else if ((st = move_aside(d, &old, err)) != SEA_OK)
            sea_temp_marker_remove(d->target);
        else if (rename(d->tmp, d->target) != 0) {
            st = sea_fail(err, SEA_ERR_IO, "%scannot rename '%s' to '%s': %s", d->pre, d->tmp,
                          d->target, strerror(errno));
            if (rename(old, d->target) == 0) /* put the old one back */
                sea_temp_marker_remove(d->target);
        } else {
            sea_temp_marker_remove(d->target);
            sea_remove_tree(old);
        }
    }
    free(old);
    if (st == SEA_OK) {
        free(d->tmp);
        d->tmp = NULL;
    }
    drop_lock(d);
    return st;
}

void sea_bake_dir_free(sea_bake_dir *d)
{
    if (d == NULL)
        return;
    if (d->tmp != NULL && d->made)
        sea_remove_tree(d->tmp);
    if (d->tmp_fd >= 0)
        close(d->tmp_fd);
    drop_lock(d);
    free(d->user);
    free(d->target);
    free(d->parent);
    free(d->lock);
    free(d->tmp);
    free(d);
}
