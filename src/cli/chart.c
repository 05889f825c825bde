/* chart.c - gnuplot charts of convergence and bench: the script built in
 * memory, gnuplot run on it with its standard output (the PNG) going to a
 * temporary file that the caller renames with its other outputs.  No user
 * string ever becomes gnuplot syntax. */
#include <errno.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"

extern char **environ;

/* Exit status of a child whose exec failed (glibc's posix_spawn, shells). */
enum { SEA_CLI_EXEC_FAILED = 127 };

FILE *sea_cli_gnuplot_begin(sea_cli_script *s, int width, int height)
{
    s->text = NULL;
    s->len = 0;
    FILE *f = s->f = open_memstream(&s->text, &s->len);
    if (f == NULL)
        return NULL;
    fprintf(f,
            "set encoding utf8\n"
            "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
            "  set terminal pngcairo size %d,%d font 'sans,10'\n"
            "} else {\n"
            "  set terminal png size %d,%d\n"
            "}\n",
            width, height, width, height);
    return f;
}

char *sea_cli_gnuplot_end(sea_cli_script *s)
{
    if (fclose(s->f) != 0) {
        free(s->text);
        return NULL;
    }
    return s->text;
}

/* Feeds script to gnuplot's standard input; gnuplot's standard output (the
 * PNG) goes to out_fd.  *absent is set when there is no gnuplot to run. */
static sea_status run_gnuplot(const char *script, int out_fd, bool *absent, sea_error *err)
{
    *absent = false;
    int fd[2];
    if (pipe(fd) != 0)
        return sea_fail(err, SEA_ERR_IO, "cannot create a pipe to gnuplot: %s", strerror(errno));
    posix_spawn_file_actions_t fa;
    if (posix_spawn_file_actions_init(&fa) != 0) {
        close(fd[0]);
        close(fd[1]);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory to run gnuplot");
    }
    FILE *log = tmpfile(); /* gnuplot's complaints, for the message */
    posix_spawn_file_actions_adddup2(&fa, fd[0], STDIN_FILENO);
    posix_spawn_file_actions_addclose(&fa, fd[0]);
    posix_spawn_file_actions_addclose(&fa, fd[1]);
    posix_spawn_file_actions_adddup2(&fa, out_fd, STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&fa, out_fd);
    if (log != NULL)
        posix_spawn_file_actions_adddup2(&fa, fileno(log), STDERR_FILENO);
    char arg0[] = "gnuplot";
    char *argv[] = {arg0, NULL};
    pid_t pid;
    int rc = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fd[0]);
    if (rc != 0) {
        close(fd[1]);
        if (log != NULL)
            fclose(log);
        if (rc == ENOENT) {
            *absent = true;
            return sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found");
        }
        return sea_fail(err, SEA_ERR_IO, "cannot run gnuplot: %s", strerror(rc));
    }
    /* A gnuplot that stops reading must not kill seabake with SIGPIPE. */
    struct sigaction ignore, saved;
    memset(&ignore, 0, sizeof ignore);
    ignore.sa_handler = SIG_IGN;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGPIPE, &ignore, &saved);
    size_t left = strlen(script);
    const char *p = script;
    while (left > 0) {
        ssize_t w = write(fd[1], p, left);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            break;
        p += w;
        left -= (size_t)w;
    }
    close(fd[1]);
    sigaction(SIGPIPE, &saved, NULL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    char first[200] = "";
    if (log != NULL) {
        rewind(log);
        /* gnuplot's first non-blank complaint line. */
        while (fgets(first, sizeof first, log) != NULL &&
               strspn(first, " \t\r\n^") == strlen(first))
            first[0] = '\0';
        first[strcspn(first, "\r\n")] = '\0';
        fclose(log);
    }
    /* Where posix_spawnp cannot report a failed exec (under valgrind, say),
     * the child exits with 127 and says nothing, as a shell would. */
    if (WIFEXITED(status) && WEXITSTATUS(status) == SEA_CLI_EXEC_FAILED && first[0] == '\0') {
        *absent = true;
        return sea_fail(err, SEA_ERR_NUMERIC, "gnuplot not found");
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || left > 0)
        return sea_fail(err, SEA_ERR_IO, "gnuplot failed%s%s", first[0] ? ": " : "", first);
    return SEA_OK;
}

/* png drawn by gnuplot into a temporary file beside it, left for the
 * caller to commit or abort with the other outputs. */
sea_status sea_cli_draw_chart(const char *png, sea_cli_chart_script_fn script_fn, const void *ctx,
                              sea_cli_atomic_file *af, bool *absent, sea_error *err)
{
    *absent = false;
    sea_status st = sea_cli_atomic_open(af, "-o", png, err);
    if (st != SEA_OK)
        return st;
    char *script = script_fn(ctx);
    if (script == NULL) {
        sea_cli_atomic_abort(af);
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the gnuplot script");
    }
    st = run_gnuplot(script, fileno(af->f), absent, err);
    free(script);
    struct stat sb;
    if (st == SEA_OK && (fstat(fileno(af->f), &sb) != 0 || sb.st_size == 0))
        st = sea_fail(err, SEA_ERR_IO, "gnuplot wrote no chart");
    if (st != SEA_OK)
        sea_cli_atomic_abort(af);
    return st;
}
