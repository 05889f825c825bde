/* fuzz_cli.c - libFuzzer target: the option scanner and the number, tuple,
 * list and frame parsers of the seabake program (src/cli/args.c), and the
 * option helpers built on them, with the real option tables of the
 * subcommands.
 *
 * Input: byte 0 picks the subcommand (its option table); the rest is split
 * at NUL bytes into argv (at most 64 arguments).  The arguments are scanned
 * with sea_cli_args_parse; when they scan, every option of the table is
 * looked up (last value, count, every value) and the helpers the
 * subcommands call are run on them (numbers, integers, seed, lists, frames,
 * tolerance, sea state, facet method, the physics inputs).  Whether or not
 * they scan, every argument is also given to sea_cli_parse_number,
 * sea_cli_parse_tuple (2 and 3 numbers) and sea_cli_parse_list, with and
 * without a range.  Nothing is computed beyond parsing, and no file is
 * written (a --water path may be read). */
#include <math.h>

#include "../../src/cli/cli.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const sea_cli_command *const COMMANDS[] = {
    &sea_cli_cmd_spectrum, &sea_cli_cmd_emissivity, &sea_cli_cmd_reflectivity,
    &sea_cli_cmd_energy,   &sea_cli_cmd_slopes,     &sea_cli_cmd_convergence,
    &sea_cli_cmd_bench,    &sea_cli_cmd_render,     &sea_cli_cmd_bake,
};

enum { ARGS_MAX = 64 };

static void check_list(const sea_cli_list *l, const sea_cli_range *r)
{
    FUZZ_ASSERT(l->n >= 1 && l->n <= SEA_CLI_LIST_MAX);
    for (size_t i = 0; i < l->n; i++) {
        const double v = l->values[i];
        FUZZ_ASSERT(!isnan(v));
        if (r) {
            FUZZ_ASSERT(r->lo_open ? v > r->lo : v >= r->lo);
            FUZZ_ASSERT(r->hi_open ? v < r->hi : v <= r->hi);
        } else {
            FUZZ_ASSERT(isfinite(v));
        }
    }
}

/* The text parsers on one string. */
static void parse_text(const char *text)
{
    static const sea_cli_range theta = {-90.0, 90.0, true, true, "degrees"};
    static const sea_cli_range closed = {0.0, INFINITY, false, false, "m"};
    static const sea_cli_range pair[2] = {{-5.0, 5.0, false, false, ""},
                                          {0.0, 10.0, false, false, ""}};
    const sea_cli_range *ranges[] = {NULL, &theta, &closed, &SEA_CLI_RANGE_WIND};
    sea_error err = {{0}};
    double v, t[3];
    for (size_t i = 0; i < sizeof ranges / sizeof *ranges; i++) {
        sea_status st = sea_cli_parse_number("--x", text, ranges[i], &v, &err);
        fuzz_check_error(st, &err);
        if (st == SEA_OK)
            FUZZ_ASSERT(!isnan(v) && (ranges[i] || isfinite(v)));
        sea_cli_list l;
        st = sea_cli_parse_list("--x", text, ranges[i], &l, &err);
        fuzz_check_error(st, &err);
        if (st == SEA_OK)
            check_list(&l, ranges[i]);
        else
            FUZZ_ASSERT(l.values == NULL);
        sea_cli_list_free(&l);
    }
    fuzz_check_error(sea_cli_parse_tuple("--x", text, 2, pair, "A,B", t, &err), &err);
    fuzz_check_error(sea_cli_parse_tuple("--x", text, 3, NULL, "A,B,C", t, &err), &err);
    long a, b;
    sea_status st = sea_cli_parse_frames(text, &a, &b, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK)
        FUZZ_ASSERT(a >= 0 && a <= b && b <= SEA_CLI_FRAME_MAX && b - a < SEA_CLI_FRAMES_MAX);
}

/* The option helpers of the subcommands on scanned arguments. */
static void use_args(const sea_cli_args *args)
{
    sea_error err = {{0}};
    for (size_t k = 0; k < args->n_options; k++) {
        const char *name = args->options[k].name;
        const char *last = sea_cli_args_get(args, name);
        size_t count = sea_cli_args_count(args, name);
        FUZZ_ASSERT((last != NULL) == (count > 0));
        for (size_t i = 0; i < count; i++)
            FUZZ_ASSERT(sea_cli_args_nth(args, name, i) != NULL);
        FUZZ_ASSERT(sea_cli_args_nth(args, name, count) == NULL);
        if (count > 0)
            FUZZ_ASSERT(sea_cli_args_nth(args, name, count - 1) == last);
        double v;
        fuzz_check_error(sea_cli_opt_number(args, name, NULL, 0.0, &v, &err), &err);
        long n;
        fuzz_check_error(sea_cli_opt_integer(args, name, -3, 1024, 0, &n, &err), &err);
        sea_cli_list l;
        if (sea_cli_opt_list(args, name, &SEA_CLI_RANGE_AZIMUTH, "0", &l, &err) == SEA_OK)
            check_list(&l, &SEA_CLI_RANGE_AZIMUTH);
        sea_cli_list_free(&l);
    }
    unsigned long seed;
    fuzz_check_error(sea_cli_opt_seed(args, &seed, &err), &err);
    sea_facet_method m;
    int n;
    sea_status st = sea_cli_opt_facet_method(args, &m, &n, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK)
        FUZZ_ASSERT(n >= 0 && n <= SEA_CLI_N_MAX);
    double wind, fetch, dir;
    st = sea_cli_opt_sea_state(args, &wind, &fetch, &dir, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK)
        FUZZ_ASSERT(wind >= SEA_WIND_MIN && wind <= SEA_WIND_MAX && fetch >= SEA_FETCH_MIN &&
                    isfinite(dir));
    bool framed;
    long a, b;
    double rate;
    st = sea_cli_opt_frames(args, &framed, &a, &b, &rate, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK)
        FUZZ_ASSERT(rate > 0.0 && isfinite(rate) && a <= b);
    sea_cli_model model;
    st = sea_cli_opt_model(args, &model, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK)
        FUZZ_ASSERT((isnan(model.tolerance) || (model.tolerance > 0.0 && model.tolerance <= 0.1)) &&
                    model.reflections >= -1 && model.reflections <= SEA_REFLECTIONS_MAX);
    const char *scene;
    fuzz_check_error(sea_cli_scene_arg(args, &scene, &err), &err);
    sea_emis_method em;
    fuzz_check_error(sea_cli_opt_emissivity(args, &em, &err), &err);
    if (sea_cli_given(args, "wavelength")) {
        sea_cli_sea sea;
        st = sea_cli_sea_inputs(args, &sea, &err);
        fuzz_check_error(st, &err);
        if (st == SEA_OK) {
            FUZZ_ASSERT(isfinite(creal(sea.N)) && isfinite(cimag(sea.N)));
            FUZZ_ASSERT(sea_slope_stats_check(&sea.stats, NULL) == SEA_OK);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    const sea_cli_command *cmd = COMMANDS[data[0] % (sizeof COMMANDS / sizeof *COMMANDS)];
    char *buf = malloc(size);
    if (!buf)
        return 0;
    memcpy(buf, data + 1, size - 1);
    buf[size - 1] = '\0';
    char *argv[ARGS_MAX + 1];
    int argc = 0;
    for (size_t at = 0; at < size - 1 && argc < ARGS_MAX; at += strlen(buf + at) + 1)
        argv[argc++] = buf + at;
    argv[argc] = NULL;

    for (int i = 0; i < argc; i++)
        parse_text(argv[i]);
    sea_cli_args args;
    sea_error err = {{0}};
    sea_status st = sea_cli_args_parse(&args, cmd->options, cmd->n_options, argc, argv, &err);
    fuzz_check_error(st, &err);
    if (st == SEA_OK && !args.help)
        use_args(&args);
    free(buf);
    return 0;
}
