/* blender.h - the Blender 3.4 import of a baked sea (issue 5; seabake(1), bake).
 * Installed as <seabake/blender.h>; ownership and the thread-safety words
 * follow seabake.h.
 *
 * The import is a Python script, exporters/blender/seabake_import.py
 * (installed for users in $(pkgdatadir)/blender), compiled into the library
 * as text so that a bake puts a copy beside every manifest without a data
 * path.  Run in Blender as
 *   blender -b --factory-startup --python seabake_import.py -- manifest.json
 * it builds the sea (one ring per clipmap level, as the POV-Ray export), the
 * sensor's camera, the sky and Cycles settings that reproduce the emission
 * maps; see the script's header.  It reads a bake directory's manifest.json
 * (<seabake/bakedir.h>: sea_bake_write with blender set writes both). */
#ifndef SEABAKE_BLENDER_H
#define SEABAKE_BLENDER_H

#include "seabake.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The name the script gets in a bake directory. */
#define SEA_BLENDER_SCRIPT "seabake_import.py"

/* The script's text, NUL-terminated (static: owned by the library).  Pure. */
const char *sea_blender_script(void);

/* Writes the script to dir/SEA_BLENDER_SCRIPT (dir must exist) through a
 * temporary beside it, renamed when complete: on failure nothing is left
 * and an existing file is untouched.  SEA_ERR_IO naming the path and the
 * system error, SEA_ERR_NOMEM.  Thread-safe. */
sea_status sea_blender_write_script(const char *dir, sea_error *err);

#ifdef __cplusplus
}
#endif
#endif /* SEABAKE_BLENDER_H */
