/* test_bakedir.c - the bake directory through the library (bakedir.h,
 * issue 42): a small bake written by sea_bake_write with both exports and
 * two frames, its manifest.json read back with cJSON (its keys, every level
 * and frame, the files the entries name, and "files", which lists every
 * file of the directory and nothing else); the same bake fed level by level
 * by the caller (as seabake bake under MPI does) gives the same bytes; the
 * previews switched off; the options' and the writer's misuses, the
 * refusal of a directory that is not a bake, and a cancelled bake that
 * leaves nothing behind. */
#define _XOPEN_SOURCE 700
#include <dirent.h>
#include <errno.h>
#include <ftw.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "bakedir.h"
#include "unit.h"

static char tmp_dir[4096];

/* A 40 x 32 view 55 deg from nadir over a few high-resolution levels and
 * the low-resolution one, small enough for two frames in a second. */
static sea_scene small_scene(void)
{
    sea_scene sc;
    sea_scene_defaults(&sc);
    sc.wind_speed = 9.0;
    sc.wind_dir = 61.7 * DEG;
    sc.altitude = 120.0;
    sc.look_zenith = 55.0 * DEG;
    sc.look_azimuth = 200.0 * DEG;
    sc.hfov = 40.0 * DEG;
    sc.width = 40;
    sc.height = 32;
    sc.wavelength = 4e-6;
    sc.method = SEA_METHOD_VARIABLE_STEP;
    sc.n = 0;
    sc.grid = 32;
    sc.emissivity_method = SEA_EMIS_FAST;
    sc.sun_zenith = 50.0 * DEG;
    sc.sun_azimuth = 200.0 * DEG;
    return sc;
}

static sea_view *prepare(const sea_scene *sc)
{
    sea_view *r = NULL;
    sea_error err;
    sea_status st = sea_view_alloc(sc, &r, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  prepare: %s\n", err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    return r;
}

static void two_frames(sea_bake_options *o)
{
    sea_bake_options_default(o);
    o->pov = 1;
    o->blender = 1;
    o->framed = 1;
    o->first = 3;
    o->last = 4;
    o->frame_rate = 10.0;
    o->scene_file = "small.ini";
}

static char *path_in(const char *dir, const char *name)
{
    static char buf[8192];
    snprintf(buf, sizeof buf, "%s/%s", dir, name);
    return buf;
}

/* The whole of a file, NUL-terminated (NULL when unreadable); *n its size. */
static char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    char *text = NULL;
    size_t len = 0, cap = 0, got;
    char chunk[65536];
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (len + got + 1 > cap) {
            cap = 2 * (len + got + 1);
            char *more = realloc(text, cap);
            if (more == NULL) {
                free(text);
                fclose(f);
                return NULL;
            }
            text = more;
        }
        memcpy(text + len, chunk, got);
        len += got;
    }
    fclose(f);
    if (text == NULL && (text = malloc(1)) == NULL)
        return NULL;
    text[len] = '\0';
    if (n != NULL)
        *n = len;
    return text;
}

static cJSON *read_manifest(const char *dir)
{
    char path[8192];
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    char *text = slurp(path, NULL);
    CU_ASSERT_PTR_NOT_NULL_FATAL(text);
    cJSON *m = cJSON_Parse(text);
    free(text);
    CU_ASSERT_PTR_NOT_NULL_FATAL(m);
    return m;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The entries of dir but dot files, sorted; returns how many (names freed
 * by the caller, at most max kept). */
static size_t list_dir(const char *dir, char **names, size_t max)
{
    DIR *d = opendir(dir);
    CU_ASSERT_PTR_NOT_NULL_FATAL(d);
    size_t n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (e->d_name[0] != '.' && n < max)
            names[n++] = strdup(e->d_name);
    closedir(d);
    qsort(names, n, sizeof *names, compare_names);
    return n;
}

/* The number of entries of dir's parent that begin with dir's name and a
 * dot (temporaries DIR.tmp.*, DIR.old.*, the lock .DIR.lock aside). */
static size_t siblings(const char *parent, const char *base)
{
    DIR *d = opendir(parent);
    CU_ASSERT_PTR_NOT_NULL_FATAL(d);
    size_t n = 0, len = strlen(base);
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        n += strncmp(e->d_name, base, len) == 0 && e->d_name[len] == '.';
    closedir(d);
    return n;
}

static int is_file(const char *dir, const char *name)
{
    struct stat sb;
    return stat(path_in(dir, name), &sb) == 0 && S_ISREG(sb.st_mode);
}

static const char *string_of(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : NULL;
}

static void bake_into(const sea_view *r, const sea_bake_options *o, const char *dir)
{
    sea_error err;
    sea_bake_stats stats;
    const sea_status st = sea_bake_write(r, o, dir, NULL, NULL, &stats, &err);
    if (st != SEA_OK)
        fprintf(stderr, "  bake %s: %s\n", dir, err.msg);
    CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
    CU_ASSERT(stats.texels > 0);
    CU_ASSERT(stats.files > 0.0 && stats.maps > 0.0);
}

/* ------------------------------------------------------------ the manifest */

/* The exports' sky (issue 45): a clear sky's table in the manifest's
 * blender object (the one sea.inc's color_map holds) against the formula,
 * [1 - (1 - eps_z)^(1 / s^2)] B(T_air) x emission_scale at s = sqrt(cos
 * zenith), computed here from sea_planck_radiance: at 20001 points of s,
 * linear between the nodes, within the error the manifest states (and
 * that within 1e-4; 8.4e-6 measured at eps_z 0.3); at most 256 nodes from
 * s = 0 to 1; the sky at the horizon is sky_emission.  An isotropic sky has
 * no table and its one radiance. */
static void test_sky_table(void)
{
    sea_scene sc = small_scene();
    sc.wavelength = 10e-6;
    sc.sky_model = SEA_SKY_CLEAR;
    sc.sky_zenith_emissivity = 0.3;
    sc.air_temperature = 283.0;
    sea_view *r = prepare(&sc);
    sea_bake_options o;
    sea_bake_options_default(&o);
    o.blender = 1;
    o.previews = 0;
    char dir[4200];
    snprintf(dir, sizeof dir, "%s/sky", tmp_dir);
    bake_into(r, &o, dir);
    cJSON *m = read_manifest(dir);
    const double scale = cJSON_GetObjectItem(m, "emission_scale")->valuedouble;
    const cJSON *b = cJSON_GetObjectItem(m, "blender");
    const cJSON *t = cJSON_GetObjectItem(b, "sky_table");
    CU_ASSERT_PTR_NOT_NULL_FATAL(t);
    const cJSON *js = cJSON_GetObjectItem(t, "s"), *jv = cJSON_GetObjectItem(t, "emission");
    const int n = cJSON_GetArraySize(js);
    CU_ASSERT_FATAL(n >= 2 && n <= 256 && cJSON_GetArraySize(jv) == n);
    double sn[256], vn[256];
    for (int i = 0; i < n; i++) {
        sn[i] = cJSON_GetArrayItem(js, i)->valuedouble;
        vn[i] = cJSON_GetArrayItem(jv, i)->valuedouble;
        CU_ASSERT(i == 0 || sn[i] > sn[i - 1]);
    }
    CU_ASSERT_EQUAL(sn[0], 0.0);
    CU_ASSERT_EQUAL(sn[n - 1], 1.0);
    const double stated = cJSON_GetObjectItem(t, "max_relative_error")->valuedouble;
    const double B = sea_planck_radiance(sc.wavelength, sc.air_temperature) * 1e-6 * scale;
    CU_ASSERT(fabs(cJSON_GetObjectItem(b, "sky_emission")->valuedouble - B) <= 1e-12 * B);
    double worst = 0.0;
    int k = 0;
    for (int j = 0; j <= 20000; j++) {
        const double x = j / 20000.0;
        while (k + 2 < n && sn[k + 1] <= x)
            k++;
        const double a = (x - sn[k]) / (sn[k + 1] - sn[k]);
        const double lin = (1.0 - a) * vn[k] + a * vn[k + 1];
        const double want = x > 0.0 ? -expm1(log(0.7) / (x * x)) * B : B;
        worst = fmax(worst, fabs(lin - want) / want);
    }
    MEASURED("sky table: %d nodes, stated error %.2g, against the formula %.2g\n", n, stated,
             worst);
    CU_ASSERT(worst <= 1.05 * stated + 1e-12);
    CU_ASSERT(stated < 1e-4);
    cJSON_Delete(m);
    sea_view_free(r);
    /* isotropic: one radiance */
    const sea_scene iso = small_scene();
    r = prepare(&iso);
    snprintf(dir, sizeof dir, "%s/sky_iso", tmp_dir);
    bake_into(r, &o, dir);
    m = read_manifest(dir);
    b = cJSON_GetObjectItem(m, "blender");
    CU_ASSERT_PTR_NULL(cJSON_GetObjectItem(b, "sky_table"));
    CU_ASSERT_PTR_NOT_NULL(cJSON_GetObjectItem(b, "sky_emission"));
    cJSON_Delete(m);
    sea_view_free(r);
}

static void test_manifest(void)
{
    const sea_scene sc = small_scene();
    sea_view *r = prepare(&sc);
    sea_bake_options o;
    two_frames(&o);
    char dir[4200];
    snprintf(dir, sizeof dir, "%s/manifest", tmp_dir);
    bake_into(r, &o, dir);
    cJSON *m = read_manifest(dir);

    CU_ASSERT_STRING_EQUAL(string_of(m, "format"), "seabake-bake");
    CU_ASSERT_EQUAL(cJSON_GetObjectItem(m, "version")->valueint, 1);
    CU_ASSERT_PTR_NOT_NULL(string_of(m, "generator"));
    CU_ASSERT_STRING_EQUAL(string_of(m, "scene_file"), "small.ini");
    CU_ASSERT(cJSON_IsTrue(cJSON_GetObjectItem(m, "framed")));
    CU_ASSERT_STRING_EQUAL(string_of(m, "pixel_type"), "float");
    CU_ASSERT_STRING_EQUAL(string_of(m, "compression"), "zip");
    static const char *const keys[] = {"scene",  "camera",  "seed",   "time_s",  "frame_rate_hz",
                                       "frames", "rows",    "units",  "levels",  "horizon",
                                       "sensor", "blender", "files",  "emission_scale",
                                       "roughness_convention"};
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
        if (!cJSON_HasObjectItem(m, keys[k])) {
            fprintf(stderr, "  manifest: no \"%s\"\n", keys[k]);
            CU_FAIL("a key is missing");
        }
    /* the emission scale is a power of ten */
    const double scale = cJSON_GetObjectItem(m, "emission_scale")->valuedouble;
    ASSERT_ABS(log10(scale), round(log10(scale)), 1e-12);
    /* the frames, at time + f / rate */
    const cJSON *frames = cJSON_GetObjectItem(m, "frames");
    CU_ASSERT_EQUAL_FATAL(cJSON_GetArraySize(frames), 2);
    for (int k = 0; k < 2; k++) {
        const cJSON *f = cJSON_GetArrayItem(frames, k);
        CU_ASSERT_EQUAL(cJSON_GetObjectItem(f, "frame")->valueint, 3 + k);
        ASSERT_ABS(cJSON_GetObjectItem(f, "time_s")->valuedouble, sc.time + (3 + k) / 10.0,
                   1e-12);
    }

    /* every level as prepared; each high-resolution level's files of each
     * frame exist under the names the entries give */
    const sea_clip_level *lv;
    const size_t nlev = sea_view_levels(r, &lv);
    const cJSON *levels = cJSON_GetObjectItem(m, "levels");
    CU_ASSERT_EQUAL_FATAL((size_t)cJSON_GetArraySize(levels), nlev);
    size_t hr = 0, named = 0;
    for (size_t l = 0; l < nlev; l++) {
        const cJSON *e = cJSON_GetArrayItem(levels, (int)l);
        CU_ASSERT_EQUAL(cJSON_GetObjectItem(e, "index")->valueint, lv[l].level);
        CU_ASSERT_EQUAL(cJSON_IsTrue(cJSON_GetObjectItem(e, "low_res")), lv[l].low_res != 0);
        if (lv[l].low_res) {
            CU_ASSERT(cJSON_HasObjectItem(e, "optics"));
            continue;
        }
        hr++;
        const cJSON *texels = cJSON_GetObjectItem(e, "texels");
        CU_ASSERT_EQUAL(cJSON_GetArrayItem(texels, 0)->valueint, (int)lv[l].nx);
        CU_ASSERT_EQUAL(cJSON_GetArrayItem(texels, 1)->valueint, (int)lv[l].ny);
        CU_ASSERT_EQUAL(cJSON_GetArraySize(cJSON_GetObjectItem(e, "maps")), 6);
        const cJSON *lf = cJSON_GetObjectItem(e, "frames");
        CU_ASSERT_EQUAL_FATAL(cJSON_GetArraySize(lf), 2);
        const cJSON *entry;
        cJSON_ArrayForEach(entry, lf)
        {
            const cJSON *group;
            cJSON_ArrayForEach(group, cJSON_GetObjectItem(entry, "files"))
            {
                for (int k = 0; k < 2; k++) {
                    const char *name = string_of(group, k ? "png" : "exr");
                    CU_ASSERT_PTR_NOT_NULL_FATAL(name);
                    CU_ASSERT(is_file(dir, name));
                    named++;
                }
            }
            const cJSON *h = cJSON_GetObjectItem(entry, "height");
            CU_ASSERT(is_file(dir, string_of(h, "png")) && is_file(dir, string_of(h, "exr")));
            CU_ASSERT(cJSON_GetObjectItem(h, "min_m")->valuedouble <
                      cJSON_GetObjectItem(h, "max_m")->valuedouble);
        }
    }
    CU_ASSERT(hr >= 2);
    CU_ASSERT_EQUAL(named, hr * 2 * 6 * 2);
    const cJSON *sensor = cJSON_GetObjectItem(cJSON_GetObjectItem(m, "sensor"), "frames");
    CU_ASSERT_EQUAL(cJSON_GetArraySize(sensor), 2);
    CU_ASSERT_STRING_EQUAL(string_of(cJSON_GetArrayItem(sensor, 1), "exr"), "sensor_0004.exr");
    CU_ASSERT_STRING_EQUAL(string_of(cJSON_GetObjectItem(m, "horizon"), "exr"), "horizon.exr");

    /* "files": sorted, unique, exactly the directory's files */
    char *names[4096];
    const size_t n = list_dir(dir, names, 4096);
    const cJSON *files = cJSON_GetObjectItem(m, "files");
    CU_ASSERT_EQUAL((size_t)cJSON_GetArraySize(files), n);
    size_t i = 0;
    const cJSON *f;
    cJSON_ArrayForEach(f, files)
    {
        CU_ASSERT_FATAL(cJSON_IsString(f));
        if (i < n && strcmp(f->valuestring, names[i]) != 0) {
            fprintf(stderr, "  files[%zu] = %s, the directory's %s\n", i, f->valuestring,
                    names[i]);
            CU_FAIL("\"files\" differs from the directory");
        }
        CU_ASSERT(is_file(dir, f->valuestring));
        i++;
    }
    static const char *const exports[] = {"manifest.json", "scene.pov",   "sea.inc",
                                          "scene.ini",     "seabake.inc", "seabake_import.py",
                                          "horizon.exr",   "sensor_0003.exr"};
    for (size_t k = 0; k < sizeof exports / sizeof exports[0]; k++) {
        int listed = 0;
        cJSON_ArrayForEach(f, files) listed |= strcmp(f->valuestring, exports[k]) == 0;
        if (!listed)
            fprintf(stderr, "  \"files\" lacks %s\n", exports[k]);
        CU_ASSERT(listed);
    }
    for (size_t k = 0; k < n; k++)
        free(names[k]);
    /* nothing beside the directory but its lock */
    CU_ASSERT_EQUAL(siblings(tmp_dir, "manifest"), 0);
    cJSON_Delete(m);
    sea_view_free(r);
}

/* ------------------------------------------ the levels given by the caller */

/* Compares every file of a with b's (the same names, the same bytes). */
static void same_tree(const char *a, const char *b)
{
    char *na[4096], *nb[4096];
    const size_t n = list_dir(a, na, 4096), m = list_dir(b, nb, 4096);
    CU_ASSERT_EQUAL(n, m);
    for (size_t i = 0; i < n && i < m; i++) {
        CU_ASSERT_STRING_EQUAL(na[i], nb[i]);
        char pa[8192], pb[8192];
        snprintf(pa, sizeof pa, "%s/%s", a, na[i]);
        snprintf(pb, sizeof pb, "%s/%s", b, nb[i]);
        size_t la = 0, lb = 0;
        char *ta = slurp(pa, &la), *tb = slurp(pb, &lb);
        const int same = ta != NULL && tb != NULL && la == lb && memcmp(ta, tb, la) == 0;
        if (!same)
            fprintf(stderr, "  %s differs from %s\n", pa, pb);
        CU_ASSERT(same);
        free(ta);
        free(tb);
    }
    for (size_t i = 0; i < n; i++)
        free(na[i]);
    for (size_t i = 0; i < m; i++)
        free(nb[i]);
}

/* The writer fed as seabake bake under MPI feeds it: each frame's levels
 * computed by sea_bake_frame_each and handed over, the sensor's image
 * rendered apart; the same directory as sea_bake_write's. */
static void test_levels_by_caller(void)
{
    const sea_scene sc = small_scene();
    sea_view *r = prepare(&sc);
    sea_bake_options o;
    two_frames(&o);
    char whole[4200], fed[4200];
    /* test_manifest's bake, or one of its own when run alone */
    snprintf(whole, sizeof whole, "%s/manifest", tmp_dir);
    struct stat sb;
    if (stat(whole, &sb) != 0)
        bake_into(r, &o, whole);
    snprintf(fed, sizeof fed, "%s/fed", tmp_dir);
    CU_ASSERT_EQUAL_FATAL(mkdir(fed, 0777), 0);
    sea_error err;
    sea_bake_writer *w = NULL;
    CU_ASSERT_EQUAL_FATAL(sea_bake_writer_alloc(r, &o, fed, NULL, NULL, &w, &err), SEA_OK);
    CU_ASSERT(sea_bake_writer_wants_view(w));
    const sea_camera *cam = sea_view_camera(r);
    for (long f = o.first; f <= o.last; f++) {
        CU_ASSERT_EQUAL(sea_bake_writer_next_frame(w), f);
        const double t = sea_bake_options_frame_time(&o, sc.time, f);
        sea_image view;
        CU_ASSERT_EQUAL_FATAL(sea_image_alloc(cam->width, cam->height, &view, &err), SEA_OK);
        CU_ASSERT_EQUAL_FATAL(sea_view_render_frame(r, t, &view, NULL, NULL, &err), SEA_OK);
        CU_ASSERT_EQUAL_FATAL(sea_bake_writer_frame_begin(w, f, &err), SEA_OK);
        sea_bake b;
        sea_status st = sea_bake_frame_each(r, t, o.view_k, &b, NULL, NULL,
                                            sea_bake_writer_level, w, &err);
        if (st != SEA_OK)
            fprintf(stderr, "  frame %ld: %s\n", f, err.msg);
        CU_ASSERT_EQUAL_FATAL(st, SEA_OK);
        CU_ASSERT_EQUAL_FATAL(sea_bake_writer_frame_end(w, &b, &view, &err), SEA_OK);
        sea_bake_free(&b);
        sea_image_free(&view);
    }
    CU_ASSERT_EQUAL(sea_bake_writer_finish(w, &err), SEA_OK);
    sea_bake_writer_free(w);
    same_tree(whole, fed);
    sea_view_free(r);
}

/* ------------------------------------------------------------- previews */

static void test_no_previews(void)
{
    const sea_scene sc = small_scene();
    sea_view *r = prepare(&sc);
    sea_view_drop_pixels(r); /* no sensor's image: none needed */
    sea_bake_options o;
    sea_bake_options_default(&o);
    o.previews = 0;
    char dir[4200];
    snprintf(dir, sizeof dir, "%s/nopng", tmp_dir);
    bake_into(r, &o, dir);
    char *names[4096];
    const size_t n = list_dir(dir, names, 4096);
    size_t png = 0, exr = 0;
    for (size_t k = 0; k < n; k++) {
        png += strstr(names[k], ".png") != NULL;
        exr += strstr(names[k], ".exr") != NULL;
        free(names[k]);
    }
    CU_ASSERT_EQUAL(png, 0);
    CU_ASSERT(exr >= 12);
    cJSON *m = read_manifest(dir);
    CU_ASSERT(cJSON_IsNull(cJSON_GetObjectItem(m, "scene_file")));
    CU_ASSERT(!cJSON_HasObjectItem(m, "sensor") && !cJSON_HasObjectItem(m, "blender"));
    const cJSON *e = cJSON_GetArrayItem(cJSON_GetObjectItem(m, "levels"), 0);
    const cJSON *files = cJSON_GetObjectItem(
        cJSON_GetArrayItem(cJSON_GetObjectItem(e, "frames"), 0), "files");
    CU_ASSERT_PTR_NOT_NULL(string_of(cJSON_GetObjectItem(files, "optics"), "exr"));
    CU_ASSERT_PTR_NULL(string_of(cJSON_GetObjectItem(files, "optics"), "png"));
    CU_ASSERT_EQUAL((size_t)cJSON_GetArraySize(cJSON_GetObjectItem(m, "files")), n);
    cJSON_Delete(m);
    sea_view_free(r);
}

/* --------------------------------------------------------------- errors */

static int stop_after(void *ctx, double fraction)
{
    (void)fraction;
    int *left = ctx;
    return --*left < 0;
}

static void test_errors(void)
{
    sea_scene sc = small_scene();
    sea_view *r = prepare(&sc);
    sea_bake_options o;
    sea_error err;
    char dir[4200];
    snprintf(dir, sizeof dir, "%s/errors", tmp_dir);

    /* options */
    sea_bake_options_default(&o);
    o.view_k = 2;
    CU_ASSERT_EQUAL(sea_bake_options_check(&o, &sc, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "view_k") != NULL);
    CU_ASSERT_EQUAL(sea_bake_write(r, &o, dir, NULL, NULL, NULL, &err), SEA_ERR_DOMAIN);
    sea_bake_options_default(&o);
    o.framed = 1;
    o.first = 5;
    o.last = 4;
    CU_ASSERT_EQUAL(sea_bake_options_check(&o, &sc, &err), SEA_ERR_DOMAIN);
    o.last = 6;
    o.frame_rate = 4.9e-324;
    CU_ASSERT_EQUAL(sea_bake_options_check(&o, &sc, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "outside") != NULL);
    sea_bake_options_default(&o);
    o.pov = 1;
    /* the exports take a directional sky and the air (issue 45) */
    sea_scene clear = sc;
    clear.sky_model = SEA_SKY_CLEAR;
    clear.sky_zenith_emissivity = 0.6174;
    clear.air_temperature = 283.0;
    clear.extinction = 2.1e-4;
    CU_ASSERT_EQUAL(sea_bake_options_check(&o, &clear, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_bake_options_check(&o, &sc, &err), SEA_OK);
    struct stat sb;
    CU_ASSERT(stat(dir, &sb) != 0 && errno == ENOENT);

    /* the writer used out of order */
    sea_bake_options_default(&o);
    CU_ASSERT_EQUAL_FATAL(mkdir(dir, 0777), 0);
    sea_bake_writer *w = NULL;
    CU_ASSERT_EQUAL_FATAL(sea_bake_writer_alloc(r, &o, dir, NULL, NULL, &w, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_bake_writer_finish(w, &err), SEA_ERR_DOMAIN);
    CU_ASSERT_EQUAL(sea_bake_writer_frame(w, &err), SEA_ERR_DOMAIN); /* failed before */
    sea_bake_writer_free(w);
    CU_ASSERT_EQUAL_FATAL(sea_bake_writer_alloc(r, &o, dir, NULL, NULL, &w, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_bake_writer_frame_begin(w, 1, &err), SEA_ERR_DOMAIN);
    sea_bake_writer_free(w);
    CU_ASSERT_EQUAL_FATAL(sea_bake_writer_alloc(r, &o, dir, NULL, NULL, &w, &err), SEA_OK);
    CU_ASSERT_EQUAL(sea_bake_writer_frame_begin(w, 0, &err), SEA_OK);
    sea_bake b;
    CU_ASSERT_EQUAL_FATAL(sea_bake_frame_each(r, sc.time, o.view_k, &b, NULL, NULL, NULL, NULL,
                                              &err),
                          SEA_OK);
    /* no level handed over */
    CU_ASSERT_EQUAL(sea_bake_writer_frame_end(w, &b, NULL, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "was not written") != NULL);
    sea_bake_free(&b);
    sea_bake_writer_free(w);

    /* a directory that is not a bake: refused, untouched */
    char notes[8192];
    snprintf(notes, sizeof notes, "%s/notes.txt", dir);
    FILE *f = fopen(notes, "w");
    CU_ASSERT_PTR_NOT_NULL_FATAL(f);
    fputs("mine\n", f);
    fclose(f);
    CU_ASSERT_EQUAL(sea_bake_write(r, &o, dir, NULL, NULL, NULL, &err), SEA_ERR_DOMAIN);
    CU_ASSERT(strstr(err.msg, "is not a bake that seabake wrote") != NULL);
    CU_ASSERT(strstr(err.msg, "choose another directory") != NULL);
    CU_ASSERT(strncmp(err.msg, "-o", 2) != 0);
    CU_ASSERT(is_file(dir, "notes.txt"));
    CU_ASSERT_EQUAL(siblings(tmp_dir, "errors"), 0);

    /* cancelled: no directory, no temporary */
    char gone[4200];
    snprintf(gone, sizeof gone, "%s/cancelled", tmp_dir);
    o.pov = 1;
    for (int stop = 0; stop < 40; stop += 13) {
        int left = stop;
        CU_ASSERT_EQUAL(sea_bake_write(r, &o, gone, stop_after, &left, NULL, &err),
                        SEA_ERR_CANCELLED);
        CU_ASSERT(strstr(err.msg, "cancelled") != NULL);
        CU_ASSERT(stat(gone, &sb) != 0 && errno == ENOENT);
        CU_ASSERT_EQUAL(siblings(tmp_dir, "cancelled"), 0);
    }
    sea_view_free(r);
}

/* ---------------------------------------------------------------- suite */

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

static int suite_init(void)
{
    const char *base = getenv("TMPDIR");
    if (base == NULL || base[0] == '\0')
        base = "/tmp";
    snprintf(tmp_dir, sizeof tmp_dir, "%s/seabake-bakedir.XXXXXX", base);
    return mkdtemp(tmp_dir) == NULL;
}

static int suite_cleanup(void)
{
    nftw(tmp_dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    return 0;
}

int test_bakedir_register(void)
{
    CU_pSuite s = CU_add_suite("bakedir", suite_init, suite_cleanup);
    if (s == NULL)
        return 1;
    return !CU_add_test(s, "manifest: keys, levels, frames, every file listed", test_manifest) ||
           !CU_add_test(s, "levels handed over by the caller: the same bytes",
                        test_levels_by_caller) ||
           !CU_add_test(s, "no previews", test_no_previews) ||
           !CU_add_test(s, "options, order, refusal, cancellation", test_errors) ||
           !CU_add_test(s, "the exports' sky table against the clear sky", test_sky_table);
}
