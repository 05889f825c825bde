/* bake.c - a bake directory for POV-Ray and Blender through libseabake.
 *
 *   bake SCENE.ini DIR
 *
 * writes into DIR (replaced atomically; an existing DIR must be empty or a
 * bake) every file of `seabake bake SCENE.ini -o DIR --pov --blender`, the
 * same bytes: the maps of every clipmap level, their previews, the
 * POV-Ray scene, the Blender import script and manifest.json.  Render them
 * with `cd DIR && povray scene.ini`, or
 * `blender -b --factory-startup --python DIR/seabake_import.py -- DIR/manifest.json`.
 *
 *   cc bake.c $(pkg-config --cflags --libs seabake) -o bake && ./bake tiny.ini out */
#include <stdio.h>

#include <seabake.h>
#include <seabake/bakedir.h>

/* Every call that can fail returns a status and fills a message. */
static int failed(const char *what, sea_status st, const sea_error *err)
{
    fprintf(stderr, "bake: %s: %s (%s)\n", what, err->msg, sea_status_name(st));
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: bake SCENE.ini DIR\n");
        return 2;
    }
    sea_init(); /* first: GSL errors become statuses instead of aborting */
    sea_error err = { { 0 } };
    sea_status st;

    /* The scene file (seabake-scene(5)), prepared once: the sensor, the
     * clipmap levels it sees, the waves, the optics. */
    sea_scene sc;
    if ((st = sea_scene_load(argv[1], &sc, &err)) != SEA_OK)
        return failed("scene", st, &err);
    sea_view *r = NULL;
    if ((st = sea_view_alloc(&sc, &r, &err)) != SEA_OK)
        return failed("prepare", st, &err);

    /* seabake bake's defaults, with both exports. */
    sea_bake_options o;
    sea_bake_options_default(&o);
    o.pov = 1;
    o.blender = 1;
    o.scene_file = argv[1]; /* as the manifest names it */

    sea_bake_stats stats;
    st = sea_bake_write(r, &o, argv[2], NULL, NULL, &stats, &err);
    sea_view_free(r);
    if (st != SEA_OK)
        return failed(argv[2], st, &err);
    printf("%s: %zu texels, %.3g s computing, %.3g s writing\n", argv[2], stats.texels,
           stats.maps, stats.files);
    return 0;
}
