/* bakedir.h - the bake directory: where `seabake bake` writes, replaced
 * atomically.  Installed as <seabake/bakedir.h>; ownership and the
 * thread-safety words follow seabake.h, and nothing here prints or exits:
 * what the program shows comes through the callbacks.
 *
 * Files go into a fresh sibling DIR.tmp.XXXXXX; the commit puts it in
 * place of DIR; a failed or abandoned bake leaves DIR as it was. */
#ifndef SEABAKE_BAKEDIR_H
#define SEABAKE_BAKEDIR_H

#include <stddef.h>

#include "exr.h"
#include "seabake.h"

#ifdef __cplusplus
extern "C" {
#endif

/* --------------------------------------------------- the atomic directory */

/* What a bake directory reports besides its errors (sea_bake_dir_hooks). */
typedef enum {
    SEA_BAKE_NOTE_WAITING, /* another bake holds the directory's lock: waiting for it */
    SEA_BAKE_NOTE_REMOVED, /* a killed bake's temporary directory was removed */
    SEA_BAKE_NOTE_RESTORED /* a directory a killed commit had moved aside was put back */
} sea_bake_note;
/* A note: text is one line, without a newline, valid during the call. */
typedef void (*sea_bake_note_fn)(void *ctx, sea_bake_note kind, const char *text);

typedef struct {
    const char *opt;       /* how messages name the directory's origin, "OPT: ..."
                              and "choose another OPT" (a program's "-o"); NULL:
                              "... choose another directory" */
    sea_bake_note_fn note; /* may be NULL */
    /* Asked (with 0) when a wait for the lock is interrupted by a signal: a
     * non-zero answer gives up (SEA_ERR_IO "cannot lock"); may be NULL. */
    sea_progress_fn progress;
    void *ctx;             /* of both */
} sea_bake_dir_hooks;

typedef struct sea_bake_dir sea_bake_dir;

/* Checks path and creates the temporary directory, before any work: its
 * parent must exist and be writable; path must not be '.', '..', '/' nor a
 * mount point; an existing path must be a directory that may be replaced,
 * which is one that is empty or a bake (a manifest.json with "format":
 * "seabake-bake" whose "files" names every other entry, each a regular
 * file): anything else is refused (SEA_ERR_DOMAIN, naming the first entry
 * the manifest does not list), untouched.  A symbolic link to a directory
 * is followed: the directory it points to is replaced, the link kept.
 *
 * Concurrency.  Creating the temporary directory and the commit happen
 * under an flock on PARENT/.BASE.lock (created once, left in place, empty),
 * so two bakes into one path both succeed, the later commit winning (a note
 * SEA_BAKE_NOTE_WAITING while one waits).  Each bake holds an flock on its
 * temporary directory while it lives: under the lock, a BASE.tmp.XXXXXX
 * whose flock can be taken belongs to a bake that was killed and is removed
 * (SEA_BAKE_NOTE_REMOVED), as is any BASE.old.XXXXXX (one exists only
 * inside a commit); if path is missing, its old copy is put back instead
 * (SEA_BAKE_NOTE_RESTORED).  Each only with seabake's marker inside, never
 * on a name alone (src/tempfile.c).
 *
 * hooks (may be NULL) are copied.  On failure *out is NULL and nothing is
 * left behind.  Thread-safe; the directory is the caller's, released with
 * sea_bake_dir_free(). */
sea_status sea_bake_dir_begin(const char *path, const sea_bake_dir_hooks *hooks,
                              sea_bake_dir **out, sea_error *err);
/* The temporary directory the files go into (owned by d; NULL once
 * committed). */
const char *sea_bake_dir_path(const sea_bake_dir *d);
/* Puts the temporary directory in place of path, under the lock: an
 * existing directory, checked again to be replaceable, is moved aside,
 * the new one renamed in, the old one removed.  On failure path is as it
 * was.  Fills d. */
sea_status sea_bake_dir_commit(sea_bake_dir *d, sea_error *err);
/* Removes the temporary directory unless committed, and frees d (NULL: a
 * no-op). */
void sea_bake_dir_free(sea_bake_dir *d);

#ifdef __cplusplus
}
#endif
#endif /* SEABAKE_BAKEDIR_H */
