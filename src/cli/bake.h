/* bake.h - what the files of seabake bake share: bake.c (options, help,
 * progress, signals, the summary line and rank 0's frame loop) and
 * bake_mpi.c (the MPI transport of frames and texel rows).  The bake
 * directory itself is the library's (<seabake/bakedir.h>). */
#ifndef SEABAKE_CLI_BAKE_H
#define SEABAKE_CLI_BAKE_H

#include <stdbool.h>
#include <stddef.h>

#include "bakedir.h"
#include "cli.h"

/* The bake's setup from its options and scene file. */
typedef struct {
    const char *scene_path;
    sea_scene sc;
    char *dir; /* -o without trailing slashes */
    sea_bake_options opt;
    bool quiet;
    bool explain;
} sea_cli_bake;

/* What a bake did: facets baked, seconds computing and writing, and the
 * parts of the computing that this process's bakes timed. */
typedef struct {
    size_t texels;
    double compute, write;
    sea_bake_times parts;
} sea_cli_bake_stats;

/* The progress bar on a terminal (on), "frame i/n". */
typedef struct {
    sea_cli_progress bar;
    bool on;
} sea_cli_bake_progress;

/* The error of a bake stopped by a signal (bake.c): "interrupted by signal
 * N: the output directory is left as it was". */
sea_status sea_cli_bake_interrupted(sea_error *err);

/* ------------------------------------------------------ MPI (bake_mpi.c) */

/* The rank that computes frame f: frames are shared round-robin. */
int sea_cli_bake_owner(const sea_cli_bake *s, long f);

/* A rank other than 0: its frames (--frames) or its texel rows of the one
 * frame, sent to rank 0 level by level. */
sea_status sea_cli_bake_send_frames(const sea_cli_bake *s, const sea_view *r, sea_error *err);
sea_status sea_cli_bake_send_rows(const sea_cli_bake *s, const sea_view *r, sea_error *err);

/* Rank 0's side: buffers for the levels of the others' frames (the largest
 * level's) and which ranks still send. */
typedef struct {
    sea_facet *moments;
    sea_facet_optics *optics;
    float *view;
    size_t nmax, view_k;
    bool *sending;
} sea_cli_bake_inbox;
sea_status sea_cli_bake_inbox_alloc(sea_cli_bake_inbox *in, const sea_cli_bake *s,
                                    const sea_view *r, sea_error *err);
/* Frame f, computed by rank owner (--frames) or by every rank's texel rows
 * (one frame), into the writer. */
sea_status sea_cli_bake_frame_mpi(sea_cli_bake_inbox *in, const sea_cli_bake *s,
                                  const sea_view *r, sea_bake_writer *w, int owner, long f,
                                  sea_cli_bake_progress *prog, sea_cli_bake_stats *stats,
                                  sea_error *err);
/* Rank owner's frame is taken (st SEA_OK: GO) or not (STOP); none for
 * rank 0's own frames. */
void sea_cli_bake_answer(sea_cli_bake_inbox *in, int owner, sea_status st);
/* After a failure at frame f: the frame each rank still has in flight,
 * received, dropped and answered STOP; then frees in. */
void sea_cli_bake_inbox_free(sea_cli_bake_inbox *in, const sea_cli_bake *s, sea_bake_writer *w,
                             long f);

#endif /* SEABAKE_CLI_BAKE_H */
