/* main.c - the seabake program: the table of subcommands and the general
 * usage; dispatches a subcommand, reports errors on stderr as one
 * "seabake: error: ..." line and maps statuses to the exit codes of
 * sea_cli_exit. */
#ifdef HAVE_CONFIG_H
#include <config.h>
#endif

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"

#ifndef PACKAGE_VERSION
#define PACKAGE_VERSION "unknown"
#endif

/* The subcommands, in the order the usage lists them. */
static const sea_cli_command *const SEA_CLI_COMMANDS[] = {
    &sea_cli_cmd_spectrum, &sea_cli_cmd_emissivity, &sea_cli_cmd_reflectivity,
    &sea_cli_cmd_energy,   &sea_cli_cmd_slopes,     &sea_cli_cmd_convergence,
    &sea_cli_cmd_bench,    &sea_cli_cmd_render,     &sea_cli_cmd_bake,
    &sea_cli_cmd_compare,  &sea_cli_cmd_convert,
};

/* The subcommand called name, or NULL. */
static const sea_cli_command *sea_cli_command_find(const char *name)
{
    for (size_t i = 0; i < SEA_CLI_COUNT(SEA_CLI_COMMANDS); ++i)
        if (strcmp(SEA_CLI_COMMANDS[i]->name, name) == 0)
            return SEA_CLI_COMMANDS[i];
    return NULL;
}

/* The general usage: synopsis, subcommands, exit codes. */
static void sea_cli_print_usage(FILE *f)
{
    fputs("Usage: seabake SUBCOMMAND [OPTIONS]\n"
          "       seabake help [SUBCOMMAND]\n"
          "       seabake --version\n"
          "\n"
          "Infrared optical properties of a wind-roughened sea surface at any\n"
          "resolution (Caillault et al. 2007, Applied Optics 46, 5471).\n"
          "\n"
          "Subcommands:\n",
          f);
    for (size_t i = 0; i < SEA_CLI_COUNT(SEA_CLI_COMMANDS); ++i)
        fprintf(f, "  %-13s %s\n", SEA_CLI_COMMANDS[i]->name, SEA_CLI_COMMANDS[i]->summary);
    fputs("  help          this text, or the options of one subcommand\n"
          "\n"
          "The physics subcommands and slopes write CSV on standard output: a\n"
          "header row, then one row per case; convergence and bench print a table\n"
          "and write their files into a directory; render writes EXR and PNG\n"
          "images of a scene file (seabake-scene(5)), bake its per-level maps and a\n"
          "manifest into a directory; compare prints a CSV row, convert writes an\n"
          "EXR's channels as .npy or CSV.  Exit status: 0 success,\n"
          "1 runtime failure, 2 usage error, 3 input/output error.  See seabake(1).\n",
          f);
}

/* Prints the error as exactly one line; usage errors point to the help.
 * Under MPI only rank 0 prints: every rank has the same error (the same
 * arguments and files, or a failure agreed by sea_cli_mpi_agree). */
static int report(sea_status status, const sea_error *err, const char *command)
{
    if (sea_cli_mpi_rank() != 0)
        return (int)sea_cli_exit_code(status);
    char msg[SEA_ERROR_MSG_MAX];
    snprintf(msg, sizeof msg, "%s", err->msg[0] ? err->msg : sea_status_name(status));
    for (char *c = msg; *c; ++c)
        if (*c == '\n' || *c == '\r')
            *c = ' ';
    sea_cli_exit code = sea_cli_exit_code(status);
    if (code == SEA_CLI_EXIT_USAGE)
        fprintf(stderr, "seabake: error: %s (see 'seabake help%s%s')\n", msg, command ? " " : "",
                command ? command : "");
    else
        fprintf(stderr, "seabake: error: %s\n", msg);
    return (int)code;
}

/* A full disk or a closed pipe shows only when the buffer is flushed. */
static int finish_output(int code)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        int saved = errno;
        if (code == SEA_CLI_EXIT_OK) {
            fprintf(stderr, "seabake: error: cannot write to standard output: %s\n",
                    saved ? strerror(saved) : "write error");
            return SEA_CLI_EXIT_IO;
        }
    }
    return code;
}

static int help(int argc, char **argv)
{
    sea_error err = {{0}};
    if (argc > 1) {
        sea_fail(&err, SEA_ERR_PARSE, "help takes at most one subcommand, got '%s'", argv[1]);
        return report(SEA_ERR_PARSE, &err, NULL);
    }
    /* under MPI the help and the version are rank 0's, as the errors */
    if (sea_cli_mpi_rank() != 0)
        return SEA_CLI_EXIT_OK;
    if (argc == 0) {
        sea_cli_print_usage(stdout);
        return SEA_CLI_EXIT_OK;
    }
    const sea_cli_command *cmd = sea_cli_command_find(argv[0]);
    if (!cmd) {
        sea_fail(&err, SEA_ERR_PARSE, "unknown subcommand '%s'", argv[0]);
        return report(SEA_ERR_PARSE, &err, NULL);
    }
    fputs(cmd->help, stdout);
    return SEA_CLI_EXIT_OK;
}

static int run(int argc, char **argv)
{
    sea_error err = {{0}};
    const char *name = argv[1];
    if (strcmp(name, "help") == 0 || strcmp(name, "--help") == 0 || strcmp(name, "-h") == 0)
        return help(argc - 2, argv + 2);
    if (strcmp(name, "--version") == 0) {
        if (argc > 2) {
            sea_fail(&err, SEA_ERR_PARSE, "--version takes no argument, got '%s'", argv[2]);
            return report(SEA_ERR_PARSE, &err, NULL);
        }
        if (sea_cli_mpi_rank() == 0)
            printf("seabake %s\n", PACKAGE_VERSION);
        return SEA_CLI_EXIT_OK;
    }
    const sea_cli_command *cmd = sea_cli_command_find(name);
    if (!cmd) {
        sea_fail(&err, SEA_ERR_PARSE,
                 name[0] == '-' ? "unknown option '%s' (a subcommand comes first)"
                                : "unknown subcommand '%s'",
                 name);
        return report(SEA_ERR_PARSE, &err, NULL);
    }
    sea_cli_args args;
    sea_status st =
        sea_cli_args_parse(&args, cmd->options, cmd->n_options, argc - 2, argv + 2, &err);
    if (st != SEA_OK)
        return report(st, &err, cmd->name);
    if (args.help) {
        if (sea_cli_mpi_rank() == 0)
            fputs(cmd->help, stdout);
        return SEA_CLI_EXIT_OK;
    }
    /* Under MPI only render and bake share their work; any other
     * subcommand would run N times over. */
    if (sea_cli_mpi_size() > 1 && cmd != &sea_cli_cmd_render && cmd != &sea_cli_cmd_bake) {
        sea_fail(&err, SEA_ERR_DOMAIN,
                 "%s does not share its work among MPI ranks: run it as one process (allowed "
                 "under MPI: render and bake)",
                 cmd->name);
        return report(SEA_ERR_DOMAIN, &err, cmd->name);
    }
    st = cmd->run(&args, stdout, &err);
    if (st != SEA_OK)
        return report(st, &err, cmd->name);
    return SEA_CLI_EXIT_OK;
}

int main(int argc, char **argv)
{
    /* A write past the file size limit (ulimit -f) raises SIGXFSZ, whose
     * default action kills the process at once (exit 153), leaving its
     * temporaries behind; ignored, the write fails with EFBIG and the
     * error path runs as on a full disk: a message, exit 3, nothing left.
     * gnuplot, started by convergence and bench, inherits it and fails
     * the same way. */
    signal(SIGXFSZ, SIG_IGN);
    sea_init();
    sea_error err = {{0}};
    sea_status st = sea_cli_mpi_init(&argc, &argv, &err);
    if (st != SEA_OK)
        return report(st, &err, NULL);
    int code;
    if (argc < 2) {
        if (sea_cli_mpi_rank() == 0)
            sea_cli_print_usage(stderr);
        code = SEA_CLI_EXIT_USAGE;
    } else {
        code = finish_output(run(argc, argv));
    }
    sea_cli_mpi_finalize();
    return code;
}
