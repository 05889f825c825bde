/* files.c - the files and directories of the subcommands: names, writable
 * parents, files written atomically (a temporary name next to the
 * destination, renamed when complete), output directories (created, their
 * parent must exist), and bake's atomic directories (a sibling
 * DIR.tmp.XXXXXX renamed over DIR when every file is in it, under a lock
 * beside DIR). */
#define _GNU_SOURCE /* renameat2 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

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

char *sea_cli_parent_dir(const char *path)
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

/* ------------------------------------------------- bake's output directory */

void sea_cli_out_dir_init(sea_cli_out_dir *od)
{
    memset(od, 0, sizeof *od);
    od->lock_fd = od->tmp_fd = -1;
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

/* Takes the lock beside the directory, waiting for another bake's commit;
 * notes the wait unless quiet. */
static sea_status take_lock(sea_cli_out_dir *od, bool quiet, sea_error *err)
{
    if (od->lock_fd < 0) {
        /* O_NOFOLLOW: a symbolic link planted under the lock's name must
         * not make the bake create or lock a file elsewhere. */
        od->lock_fd = open(od->lock, O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0666);
        /* another user's lock file: flock needs no write access */
        if (od->lock_fd < 0 && errno == EACCES)
            od->lock_fd = open(od->lock, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
        if (od->lock_fd < 0 && errno == ELOOP)
            return sea_fail(err, SEA_ERR_IO,
                            "-o: the lock file '%s' is a symbolic link; remove it (seabake "
                            "makes it as an empty file)",
                            od->lock);
        if (od->lock_fd < 0)
            return sea_fail(err, SEA_ERR_IO, "-o: cannot create the lock file '%s': %s",
                            od->lock, strerror(errno));
        struct stat sb;
        if (fstat(od->lock_fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
            close(od->lock_fd);
            od->lock_fd = -1;
            return sea_fail(err, SEA_ERR_IO,
                            "-o: the lock file '%s' is not a regular file; remove it (seabake "
                            "makes it as an empty file)",
                            od->lock);
        }
    }
    if (flock(od->lock_fd, LOCK_EX | LOCK_NB) == 0)
        return SEA_OK;
    if (errno != EWOULDBLOCK)
        return SEA_OK; /* no flock on this file system: unlocked, as before */
    if (!quiet)
        fprintf(stderr, "bake: waiting for another bake to finish writing '%s'\n", od->user);
    while (flock(od->lock_fd, LOCK_EX) != 0) {
        if (errno != EINTR || sea_cli_interrupted() != 0)
            return sea_fail(err, SEA_ERR_IO, "-o: cannot lock '%s': %s", od->lock,
                            strerror(errno));
    }
    return SEA_OK;
}

static void drop_lock(sea_cli_out_dir *od)
{
    if (od->lock_fd >= 0) {
        flock(od->lock_fd, LOCK_UN);
        close(od->lock_fd);
        od->lock_fd = -1;
    }
}

/* ------------------------------------------ what seabake may remove or replace
 *
 * seabake removes or replaces a directory only when it can show that it
 * wrote it: never on a name alone.
 *
 * Its temporaries (DIR.tmp.XXXXXX while a bake runs, DIR.old.XXXXXX inside
 * a commit, FILE.tmp.XXXXXX while a file is written) hold a marker file,
 * SEA_TEMP_MARKER, written by the process that made them (src/tempfile.c):
 * "kind tmp", "kind old" or "kind file", "target BASE" (the directory or
 * file it belongs to), and the process's pid and host.  A directory named
 * like a temporary without that marker, or whose marker names another kind
 * or target, or that another user owns, is left alone.
 *
 * A bake directory that may be replaced is empty, or holds a manifest.json
 * with "format": "seabake-bake" whose "files" list names every other entry,
 * each a regular file (the marker of an interrupted commit aside). */

/* A manifest is a few hundred kilobytes at most (a thousand frames of six
 * levels); anything far larger is not one of seabake's. */
static const long SEA_CLI_MANIFEST_MAX = 64L << 20;

/* "BASE.tmp.XXXXXX" (1) or "BASE.old.XXXXXX" (2), six letters or digits
 * as mkdtemp and old_name make them; 0 otherwise.  A candidate only: the
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
    char *path = sea_cli_path_join(dir, "manifest.json");
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
    if (fd >= 0 && fstat(fd, &sb) == 0 && S_ISREG(sb.st_mode) && sb.st_size <= SEA_CLI_MANIFEST_MAX &&
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
static bool manifest_lists(const cJSON *files, const char *name)
{
    const cJSON *f;
    cJSON_ArrayForEach(f, files)
    {
        if (cJSON_IsString(f) && strcmp(f->valuestring, name) == 0)
            return true;
    }
    return false;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* SEA_OK if the existing directory od->target may be replaced by a bake
 * (the rule above); otherwise SEA_ERR_DOMAIN naming what was found and how
 * to proceed.  Nothing is changed. */
static sea_status check_replaceable(const sea_cli_out_dir *od, sea_error *err)
{
    DIR *d = opendir(od->target);
    if (d == NULL)
        return sea_fail(err, SEA_ERR_IO, "-o: cannot read the directory '%s': %s", od->user,
                        strerror(errno));
    /* the entries, sorted, so that the message is the same on every run */
    char **names = NULL;
    size_t n = 0, cap = 0;
    bool has_manifest = false, nomem = false;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0 ||
            strcmp(e->d_name, SEA_TEMP_MARKER) == 0)
            continue;
        if (strcmp(e->d_name, "manifest.json") == 0) {
            has_manifest = true;
            continue;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 16;
            char **more = realloc(names, cap * sizeof *names);
            if (more == NULL) {
                nomem = true;
                break;
            }
            names = more;
        }
        if ((names[n] = strdup(e->d_name)) == NULL) {
            nomem = true;
            break;
        }
        ++n;
    }
    closedir(d);
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
    } else if ((m = read_manifest(od->target, &why)) != NULL) {
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
            char *path = sea_cli_path_join(od->target, names[i]);
            const bool regular = path != NULL && lstat(path, &sb) == 0 && S_ISREG(sb.st_mode);
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
                          "-o: '%s' is not a bake that seabake wrote (%s '%s'%s); seabake "
                          "replaces only its own bakes: choose another -o, or move or remove "
                          "'%s' yourself",
                          od->user, why, bad, more, od->user);
        else
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "-o: '%s' is not a bake that seabake wrote (%s); seabake replaces only "
                          "its own bakes: choose another -o, or move or remove '%s' yourself",
                          od->user, why, od->user);
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
 * lock) to its end, so one whose flock can be taken is stale; a DIR.old.XXXXXX
 * exists only inside a commit, which holds this lock, so any is stale.  A
 * bake killed between moving DIR aside and putting the new one in place
 * left DIR missing: its old copy is put back.  Each only with seabake's
 * marker inside (above). */
static void clean_stale(sea_cli_out_dir *od)
{
    DIR *d = opendir(od->parent);
    if (d == NULL)
        return;
    size_t blen;
    const char *base = base_name(od->target, &blen);
    char *b = strndup(base, blen);
    const uid_t me = geteuid();
    struct dirent *e;
    while (b != NULL && (e = readdir(d)) != NULL) {
        const int kind = temporary_kind(e->d_name, b, blen);
        if (kind == 0)
            continue;
        char *path = sea_cli_path_join(od->parent, e->d_name);
        struct stat sb;
        if (path == NULL || lstat(path, &sb) != 0 || !S_ISDIR(sb.st_mode) || sb.st_uid != me ||
            !sea_temp_marker_is(path, kind == 1 ? "tmp" : "old", b, blen)) {
            free(path);
            continue;
        }
        bool stale = kind == 2;
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
        if (kind == 2 && lstat(od->target, &tb) != 0 && errno == ENOENT &&
            rename(path, od->target) == 0) {
            sea_temp_marker_remove(od->target);
            fprintf(stderr,
                    "bake: '%s' restored from '%s', left by a bake that was killed while "
                    "replacing it\n",
                    od->user, e->d_name);
        } else if (sea_cli_remove_tree(path) == 0) {
            fprintf(stderr, "bake: removed '%s', left by a bake that was killed\n", path);
        }
        free(path);
    }
    free(b);
    closedir(d);
}

/* Moves the existing target aside to a fresh DIR.old.XXXXXX; *old gets its
 * name.  renameat2's RENAME_NOREPLACE makes the name without a directory
 * to rename onto; where the file system lacks it, mkdtemp reserves the name
 * and rename replaces that empty directory (POSIX). */
static sea_status move_aside(const sea_cli_out_dir *od, char **old, sea_error *err)
{
    if ((*old = sea_cli_sibling_template(od->target, "old")) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    static const char letters[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
    char *x = *old + strlen(*old) - 6;
    for (int attempt = 0; attempt < 100; ++attempt) {
        unsigned char r[6];
        if (getrandom(r, sizeof r, 0) != (ssize_t)sizeof r)
            break;
        for (int i = 0; i < 6; ++i)
            x[i] = letters[r[i] % (sizeof letters - 1)];
        if (renameat2(AT_FDCWD, od->target, AT_FDCWD, *old, RENAME_NOREPLACE) == 0)
            return SEA_OK;
        if (errno != EEXIST)
            break;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != EEXIST)
        return sea_fail(err, SEA_ERR_IO, "-o: cannot move '%s' aside: %s", od->target,
                        strerror(errno));
    memcpy(x, "XXXXXX", 6);
    if (mkdtemp(*old) == NULL)
        return sea_fail(err, SEA_ERR_IO, "-o: cannot create a directory in '%s': %s", od->parent,
                        strerror(errno));
    if (rename(od->target, *old) != 0) {
        const int e = errno;
        rmdir(*old);
        return sea_fail(err, SEA_ERR_IO, "-o: cannot move '%s' aside to '%s': %s", od->target,
                        *old, strerror(e));
    }
    return SEA_OK;
}

sea_status sea_cli_out_dir_begin(sea_cli_out_dir *od, const char *dir, bool quiet, sea_error *err)
{
    sea_cli_out_dir_init(od);
    size_t blen;
    const char *base = base_name(dir, &blen);
    if (dir[0] == '\0')
        return sea_fail(err, SEA_ERR_PARSE, "-o: empty directory name");
    if (blen == 0 || (blen == 1 && base[0] == '.') || (blen == 2 && strncmp(base, "..", 2) == 0))
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "-o: '%s' cannot be replaced by the bake (name the directory itself, "
                        "not '.', '..' or '/')",
                        dir);
    if ((od->user = strndup(dir, (size_t)(base - dir) + blen)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    /* A symbolic link to a directory: the bake replaces the directory it
     * points to (built beside it, on its file system), the link stays. */
    struct stat sb;
    if (lstat(od->user, &sb) == 0 && S_ISLNK(sb.st_mode)) {
        struct stat tb;
        if (stat(od->user, &tb) != 0)
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "-o: '%s' is a symbolic link to nothing (%s)", od->user,
                            strerror(errno));
        if (!S_ISDIR(tb.st_mode))
            return sea_fail(err, SEA_ERR_IO, "-o: '%s' exists and is not a directory",
                            od->user);
        od->target = realpath(od->user, NULL);
        if (od->target == NULL)
            return sea_fail(err, SEA_ERR_IO, "-o: cannot resolve '%s': %s", od->user,
                            strerror(errno));
        if (strcmp(od->target, "/") == 0)
            return sea_fail(err, SEA_ERR_DOMAIN, "-o: '%s' points to '/', which cannot be "
                                                 "replaced", od->user);
    } else if ((od->target = strdup(od->user)) == NULL) {
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    }
    if ((od->parent = sea_cli_parent_dir(od->target)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    sea_status st = check_dir_exists("-o", od->parent, err);
    if (st != SEA_OK)
        return st;
    base = base_name(od->target, &blen);
    const size_t llen = strlen(od->parent) + blen + 8;
    if ((od->lock = malloc(llen)) == NULL ||
        (od->tmp = sea_cli_sibling_template(od->target, "tmp")) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory");
    snprintf(od->lock, llen, "%s/.%.*s.lock", od->parent, (int)blen, base);

    /* A file where the directory should be is refused before the lock file
     * is made (which would stay behind); under the lock it is checked again. */
    if (lstat(od->target, &sb) == 0 && !S_ISDIR(sb.st_mode))
        return sea_fail(err, SEA_ERR_IO, "-o: '%s' exists and is not a directory", od->user);
    if ((st = take_lock(od, quiet, err)) != SEA_OK)
        return st;
    clean_stale(od);
    if (lstat(od->target, &sb) == 0) {
        struct stat pb;
        if (!S_ISDIR(sb.st_mode))
            st = sea_fail(err, SEA_ERR_IO, "-o: '%s' exists and is not a directory",
                          od->user);
        else if (stat(od->parent, &pb) == 0 && pb.st_dev != sb.st_dev)
            st = sea_fail(err, SEA_ERR_DOMAIN,
                          "-o: '%s' is a mount point, which cannot be replaced (bake into a "
                          "directory inside it)",
                          od->user);
        else
            st = check_replaceable(od, err);
    } else if (errno != ENOENT) {
        st = sea_fail(err, SEA_ERR_IO, "-o: cannot examine '%s': %s", od->user, strerror(errno));
    }
    if (st == SEA_OK && mkdtemp(od->tmp) == NULL) {
        st = sea_fail(err, SEA_ERR_IO, "-o: cannot create a directory in '%s': %s", od->parent,
                      strerror(errno));
        free(od->tmp);
        od->tmp = NULL;
    }
    od->made = st == SEA_OK;
    if (st == SEA_OK) {
        const int e = sea_temp_marker_write(od->tmp, "tmp", base, blen);
        if (e != 0)
            st = sea_fail(err, SEA_ERR_IO, "-o: cannot write into '%s': %s", od->tmp,
                          strerror(e));
    }
    if (st == SEA_OK) {
        /* The flock that tells other bakes this temporary is alive.  Where
         * the file system has no flock, theirs fails too and they keep it. */
        od->tmp_fd = open(od->tmp, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (od->tmp_fd >= 0)
            flock(od->tmp_fd, LOCK_EX | LOCK_NB);
        /* mkdtemp makes it 0700; DIR gets the umask's permissions */
        if (chmod(od->tmp, 0777 & ~sea_cli_umask()) != 0)
            st = sea_fail(err, SEA_ERR_IO, "-o: cannot set the permissions of '%s': %s", od->tmp,
                          strerror(errno));
    }
    drop_lock(od);
    return st;
}

/* Puts the finished temporary directory in place of the target, under the
 * lock: an existing directory, checked again to be a bake, is marked and
 * renamed aside, the new one renamed in, the old one removed, all before
 * another bake may commit. */
sea_status sea_cli_out_dir_commit(sea_cli_out_dir *od, bool quiet, sea_error *err)
{
    sea_status st = take_lock(od, quiet, err);
    if (st != SEA_OK)
        return st;
    size_t blen;
    const char *base = base_name(od->target, &blen);
    struct stat sb;
    char *old = NULL;
    if (lstat(od->target, &sb) != 0) {
        if (rename(od->tmp, od->target) != 0)
            st = sea_fail(err, SEA_ERR_IO, "-o: cannot rename '%s' to '%s': %s", od->tmp,
                          od->target, strerror(errno));
        else
            sea_temp_marker_remove(od->target);
    } else if (!S_ISDIR(sb.st_mode)) {
        st = sea_fail(err, SEA_ERR_IO, "-o: '%s' exists and is not a directory", od->user);
    } else if ((st = check_replaceable(od, err)) != SEA_OK) {
        /* something was put into DIR while the bake ran */
    } else {
        /* A marker left by a commit killed before its rename is replaced. */
        sea_temp_marker_remove(od->target);
        int e = sea_temp_marker_write(od->target, "old", base, blen);
        if (e != 0)
            st = sea_fail(err, SEA_ERR_IO, "-o: cannot write into '%s': %s", od->user,
                          strerror(e));
        else if ((st = move_aside(od, &old, err)) != SEA_OK)
            sea_temp_marker_remove(od->target);
        else if (rename(od->tmp, od->target) != 0) {
            st = sea_fail(err, SEA_ERR_IO, "-o: cannot rename '%s' to '%s': %s", od->tmp,
                          od->target, strerror(errno));
            if (rename(old, od->target) == 0) /* put the old one back */
                sea_temp_marker_remove(od->target);
        } else {
            sea_temp_marker_remove(od->target);
            sea_cli_remove_tree(old);
        }
    }
    free(old);
    if (st == SEA_OK) {
        free(od->tmp);
        od->tmp = NULL;
    }
    drop_lock(od);
    return st;
}

/* Removes the temporary directory (if any) and releases everything. */
void sea_cli_out_dir_end(sea_cli_out_dir *od)
{
    if (od->tmp != NULL && od->made)
        sea_cli_remove_tree(od->tmp);
    if (od->tmp_fd >= 0)
        close(od->tmp_fd);
    drop_lock(od);
    free(od->user);
    free(od->target);
    free(od->parent);
    free(od->lock);
    free(od->tmp);
    sea_cli_out_dir_init(od);
}
