/* bake_mpi.c - seabake bake under mpirun or srun (seabake(1), PARALLEL
 * RUNS WITH MPI): the frames, or the texel rows of one frame, computed by
 * the ranks and handed to rank 0's bake writer (<seabake/bakedir.h>)
 * level by level, so that the directory is that of one process, byte for
 * byte.  The library computes (sea_bake_frame_each, sea_bake_frame_rows)
 * and writes (sea_bake_writer_level, _frame_end); the messages between
 * the ranks are the program's (mpi.c). */
#include <assert.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "bake.h"

/* A frame computed here fills the progress bar's first COMPUTE_SHARE with
 * its computation, as the writer's own frames do (bakedir.c). */
static const double COMPUTE_SHARE = 0.9;

/* The progress of a frame computed by the program (bar.index set): the bar
 * on a terminal, and a stop as soon as a signal came. */
static int sea_cli_bake_progress_compute(void *ctx, double fraction)
{
    sea_cli_bake_progress *p = ctx;
    return sea_cli_progress_if(&p->bar, p->on, COMPUTE_SHARE * fraction);
}

/* ------------------------------------------------------------------ MPI
 *
 * Under mpirun or srun with N > 1 ranks (mpi.c; seabake(1), PARALLEL RUNS
 * WITH MPI) the frames of --frames A:B are shared round-robin: frame f is
 * computed by rank (f - A) mod N.  Rank 0 is the one writer: it owns the
 * temporary directory and writes every file, in frame order, exactly as one
 * process does (its own frames through sea_bake_writer_frame, the others'
 * levels as they arrive, through sea_bake_writer_level), so the directory
 * is that of one process byte for byte; frame A, which sets the emission
 * scale and the previews' tone curves, is always rank 0's.  Another rank
 * queues each level of its frame as it is computed (bake_msg, then a copy
 * of the level's moments, optics and view texels as bytes: the ranks run
 * the same program on the same kind of machine), so that it computes its
 * whole frame while rank 0 is on earlier ones, then sends an END message
 * with its status and the frame's headers, and waits until rank 0 has
 * taken the frame and answered: so at most one frame a rank is in flight
 * (its maps held in the queue), and a failure
 * anywhere (a rank's computation, rank 0's writing, a signal) is answered
 * with STOP to every rank still sending, whose frame in flight rank 0
 * receives and drops.  Rank 0 then removes the temporary directory, and
 * every rank leaves with rank 0's error.  One frame (no --frames) is
 * shared by texel rows instead: see bake_rows_frame. */
enum { BAKE_MSG_LEVEL, BAKE_MSG_END };
enum { BAKE_TAG_MSG = 1, BAKE_TAG_DATA, BAKE_TAG_ACK };
enum { BAKE_ACK_GO = 0, BAKE_ACK_STOP = 1 };
typedef struct {
    int kind, status;
    size_t level, bytes; /* bytes: of a rows message's data */
    sea_error err;
    sea_bake b; /* the headers; pointers not meaningful */
} bake_msg;

int sea_cli_bake_owner(const sea_cli_bake *s, long f)
{
    return (int)((f - (s->opt.framed ? s->opt.first : 0)) % sea_cli_mpi_size());
}

/* A copy of n bytes of p, queued to rank 0. */
static sea_status queue_copy(sea_cli_mpi_queue *q, const void *p, size_t n, int tag,
                             sea_error *err)
{
    void *copy = malloc(n + 1);
    if (copy == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the maps sent to rank 0");
    memcpy(copy, p, n);
    return sea_cli_mpi_queue_send(q, copy, n, 0, tag, err);
}

/* sea_bake_level_fn of a rank other than 0: level l queued to rank 0 (a
 * copy: the library frees its maps), so that the rank computes its whole
 * frame while rank 0 is still on earlier ones. */
typedef struct {
    sea_cli_mpi_queue q;
    bool broken; /* a level queued in part (no memory for a copy) */
} bake_outbox;

static sea_status level_send(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    bake_outbox *out = ctx;
    sea_cli_mpi_queue *q = &out->q;
    if (sea_cli_interrupted() != 0)
        return sea_cli_bake_interrupted(err);
    bake_msg m;
    memset(&m, 0, sizeof m);
    m.kind = BAKE_MSG_LEVEL;
    m.level = l;
    m.b = *b;
    const sea_bake_level *bl = &b->levels[l];
    const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
    sea_status st = queue_copy(q, &m, sizeof m, BAKE_TAG_MSG, err);
    if (st == SEA_OK)
        st = queue_copy(q, bl->moments, n * sizeof *bl->moments, BAKE_TAG_DATA, err);
    if (st == SEA_OK)
        st = queue_copy(q, bl->optics, n * sizeof *bl->optics, BAKE_TAG_DATA, err);
    if (st == SEA_OK)
        st = queue_copy(q, bl->view, nv * sizeof *bl->view, BAKE_TAG_DATA, err);
    out->broken = st != SEA_OK;
    return st;
}

/* A rank other than 0: its frames, each level to rank 0 (see above).  A
 * level whose copy failed for memory was not queued whole: the END that
 * follows cannot be told apart, so that failure aborts the job. */
sea_status sea_cli_bake_send_frames(const sea_cli_bake *s, const sea_view *r, sea_error *err)
{
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    const long first = s->opt.framed ? s->opt.first : 0, last = s->opt.framed ? s->opt.last : 0;
    sea_status st = SEA_OK;
    bake_outbox out = {{NULL, NULL, 0, 0}, false};
    sea_cli_mpi_queue *q = &out.q;
    sea_cli_mpi_queue_init(q);
    for (long f = first + rank; f <= last; f += size) {
        const double t = sea_bake_options_frame_time(&s->opt, s->sc.time, f);
        sea_cli_bake_progress prog = {{"bake", 0, 1, -1, 0.0}, false};
        sea_bake b;
        st = sea_bake_frame_each(r, t, s->opt.view_k, &b, sea_cli_bake_progress_compute, &prog,
                                 level_send, &out, err);
        bake_msg m;
        memset(&m, 0, sizeof m);
        m.kind = BAKE_MSG_END;
        if (st == SEA_OK) {
            m.b = b;
            sea_bake_free(&b);
        }
        if (out.broken)
            sea_cli_mpi_abort(err);
        /* as rank 0's: a signal's message, whatever stopped the bake */
        if (sea_cli_interrupted() != 0)
            st = sea_cli_bake_interrupted(err);
        m.status = (int)st;
        if (st != SEA_OK && err != NULL)
            m.err = *err;
        sea_cli_mpi_send(&m, sizeof m, 0, BAKE_TAG_MSG);
        /* rank 0 has taken the frame: then its answer */
        sea_cli_mpi_queue_wait(q);
        int ack = BAKE_ACK_STOP;
        sea_cli_mpi_recv(&ack, sizeof ack, 0, BAKE_TAG_ACK);
        if (st != SEA_OK || ack != BAKE_ACK_GO)
            break;
    }
    sea_cli_mpi_queue_free(q);
    return st;
}

/* Rank 0: frame f of rank k, each level written as it arrives (when st is
 * SEA_OK: otherwise received and dropped) until its END, whose headers go
 * to *b (no maps).  The first failure, rank 0's or rank k's, is returned. */
static sea_status bake_recv_frame(sea_bake_writer *w, sea_cli_bake_inbox *in, int k, sea_status st,
                                  sea_bake *b, sea_error *err)
{
    bake_msg m;
    for (;;) {
        sea_cli_mpi_recv(&m, sizeof m, k, BAKE_TAG_MSG);
        if (m.kind == BAKE_MSG_END)
            break;
        sea_bake_level *bl = &m.b.levels[m.level];
        const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
        /* the same levels as rank 0's (one prepare): within the inbox */
        assert(n <= in->nmax && bl->view_k == in->view_k);
        sea_cli_mpi_recv(in->moments, n * sizeof *in->moments, k, BAKE_TAG_DATA);
        sea_cli_mpi_recv(in->optics, n * sizeof *in->optics, k, BAKE_TAG_DATA);
        sea_cli_mpi_recv(in->view, nv * sizeof *in->view, k, BAKE_TAG_DATA);
        bl->moments = in->moments;
        bl->optics = in->optics;
        bl->view = in->view;
        if (st == SEA_OK)
            st = sea_bake_writer_level(w, &m.b, m.level, err);
    }
    if (st == SEA_OK && m.status != SEA_OK) {
        st = (sea_status)m.status;
        if (err != NULL)
            *err = m.err;
    }
    *b = m.b;
    for (size_t l = 0; l < SEA_CLIP_MAX_LEVELS; l++) {
        b->levels[l].moments = NULL;
        b->levels[l].optics = NULL;
        b->levels[l].view = NULL;
    }
    return st;
}

/* One frame (no --frames) under MPI: shared by texel rows.  Rank k bakes
 * texel rows k, k + N, ... of every level (sea_bake_frame_rows; every rank
 * synthesises the frame's waves itself) and, per level, sends rank 0 a
 * BAKE_MSG_LEVEL then its rows' optics and view texels, and waits for GO
 * or STOP; then an END with its status.  Rank 0 assembles each level (its
 * own rows, the others', the moments it has whole) and writes it through
 * sea_bake_writer_level, as one process does, then answers every rank.  A rank's
 * failure reaches rank 0 as its END; rank 0 then answers STOP, and after
 * its own bake drains every rank to its END. */
typedef struct {
    sea_bake_writer *w; /* rank 0 */
    sea_cli_bake_inbox *in;     /* rank 0: the level assembled */
    bool *open;         /* rank 0: ranks whose END has not come */
    bool failed;        /* rank 0 failed before the frame: receive, write nothing */
} bake_rows_ctx;

/* Bytes of one texel row of a level in a rank's message: its optics, then
 * its view_k rows of view texels. */
static size_t row_bytes(const sea_bake_level *bl)
{
    return bl->level.nx *
           (sizeof(sea_facet_optics) + bl->view_k * bl->view_k * sizeof(float));
}

/* Rank k's rows of level bl into (pack) or out of (unpack) buf. */
static void rows_pack(sea_bake_level *bl, int k, int size, unsigned char *buf, bool pack)
{
    const size_t nx = bl->level.nx, nv = bl->view_k * bl->view_k * nx;
    for (size_t row = (size_t)k; row < bl->level.ny; row += (size_t)size) {
        sea_facet_optics *o = bl->optics + row * nx;
        float *v = bl->view + row * nv;
        if (pack) {
            memcpy(buf, o, nx * sizeof *o);
            memcpy(buf + nx * sizeof *o, v, nv * sizeof *v);
        } else {
            memcpy(o, buf, nx * sizeof *o);
            memcpy(v, buf + nx * sizeof *o, nv * sizeof *v);
        }
        buf += row_bytes(bl);
    }
}

/* sea_bake_level_fn of a rank other than 0 (rows). */
static sea_status rows_send(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    (void)ctx;
    if (sea_cli_interrupted() != 0)
        return sea_cli_bake_interrupted(err);
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    sea_bake_level bl = b->levels[l];
    const size_t bytes = sea_cli_mpi_share(bl.level.ny, rank, size) * row_bytes(&bl);
    unsigned char *buf = malloc(bytes + 1);
    if (buf == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the rows sent to rank 0");
    rows_pack(&bl, rank, size, buf, true);
    bake_msg m;
    memset(&m, 0, sizeof m);
    m.kind = BAKE_MSG_LEVEL;
    m.level = l;
    m.bytes = bytes;
    sea_cli_mpi_send(&m, sizeof m, 0, BAKE_TAG_MSG);
    sea_cli_mpi_send(buf, bytes, 0, BAKE_TAG_DATA);
    free(buf);
    int ack = BAKE_ACK_STOP;
    sea_cli_mpi_recv(&ack, sizeof ack, 0, BAKE_TAG_ACK);
    /* stopped: rank 0 holds the failure that it will report */
    return ack == BAKE_ACK_GO ? SEA_OK : sea_fail(err, SEA_ERR_CANCELLED, "stopped by rank 0");
}

/* A rank other than 0: its rows of the one frame (see above). */
sea_status sea_cli_bake_send_rows(const sea_cli_bake *s, const sea_view *r, sea_error *err)
{
    const int rank = sea_cli_mpi_rank(), size = sea_cli_mpi_size();
    sea_cli_bake_progress prog = {{"bake", 0, 1, -1, 0.0}, false};
    sea_bake b;
    sea_status st = sea_bake_frame_rows(r, s->sc.time, s->opt.view_k, rank, size, &b,
                                        sea_cli_bake_progress_compute, &prog, rows_send, NULL, err);
    if (st == SEA_OK)
        sea_bake_free(&b);
    if (sea_cli_interrupted() != 0)
        st = sea_cli_bake_interrupted(err);
    bake_msg m;
    memset(&m, 0, sizeof m);
    m.kind = BAKE_MSG_END;
    m.status = (int)st;
    if (st != SEA_OK && err != NULL)
        m.err = *err;
    sea_cli_mpi_send(&m, sizeof m, 0, BAKE_TAG_MSG);
    return st;
}

/* Rank 0: the next message of rank k; a level's rows into bl (or dropped
 * when bl is NULL).  Returns its kind; an END's failure into *st, *err
 * unless *st already failed. */
static int rows_recv(int k, sea_bake_level *bl, sea_status *st, sea_error *err)
{
    bake_msg m;
    sea_cli_mpi_recv(&m, sizeof m, k, BAKE_TAG_MSG);
    if (m.kind == BAKE_MSG_END) {
        if (*st == SEA_OK && m.status != SEA_OK) {
            *st = (sea_status)m.status;
            if (err != NULL)
                *err = m.err;
        }
        return BAKE_MSG_END;
    }
    /* the level of rank 0's own bake: the same headers (one prepare) */
    unsigned char *buf = NULL;
    if (bl != NULL) {
        assert(m.bytes == sea_cli_mpi_share(bl->level.ny, k, sea_cli_mpi_size()) * row_bytes(bl));
        if ((buf = malloc(m.bytes + 1)) == NULL && *st == SEA_OK)
            *st = sea_fail(err, SEA_ERR_NOMEM, "out of memory for the rows of rank %d", k);
    }
    if (buf != NULL) {
        sea_cli_mpi_recv(buf, m.bytes, k, BAKE_TAG_DATA);
        rows_pack(bl, k, sea_cli_mpi_size(), buf, false);
        free(buf);
    } else {
        sea_cli_mpi_drop(m.bytes, k, BAKE_TAG_DATA);
    }
    return BAKE_MSG_LEVEL;
}

/* sea_bake_level_fn of rank 0 (rows): the level assembled and written. */
static sea_status rows_gather(void *ctx, const sea_bake *b, size_t l, sea_error *err)
{
    bake_rows_ctx *c = ctx;
    const int size = sea_cli_mpi_size();
    sea_bake whole = *b;
    sea_bake_level *bl = &whole.levels[l];
    const size_t n = bl->level.nx * bl->level.ny, nv = n * bl->view_k * bl->view_k;
    memcpy(c->in->moments, bl->moments, n * sizeof *bl->moments);
    memcpy(c->in->optics, bl->optics, n * sizeof *bl->optics);
    memcpy(c->in->view, bl->view, nv * sizeof *bl->view);
    bl->moments = c->in->moments;
    bl->optics = c->in->optics;
    bl->view = c->in->view;
    sea_status st = sea_cli_interrupted() != 0 ? sea_cli_bake_interrupted(err)
                    : c->failed ? sea_fail(err, SEA_ERR_CANCELLED, "stopped by rank 0")
                                : SEA_OK;
    for (int k = 1; k < size; k++)
        if (c->open[k] && rows_recv(k, bl, &st, err) == BAKE_MSG_END)
            c->open[k] = false;
    if (st == SEA_OK)
        st = sea_bake_writer_level(c->w, &whole, l, err);
    const int ack = st == SEA_OK ? BAKE_ACK_GO : BAKE_ACK_STOP;
    for (int k = 1; k < size; k++)
        if (c->open[k])
            sea_cli_mpi_send(&ack, sizeof ack, k, BAKE_TAG_ACK);
    return st;
}

/* Rank 0: the one frame by rows, then every other rank to its END (a
 * level still coming is dropped and answered STOP); failed: rank 0 failed
 * before the frame, which it then only receives. */
static sea_status bake_rows_frame(sea_bake_writer *w, sea_cli_bake_inbox *in, bool *open,
                                  const sea_view *r, double t, int view_k, bool failed,
                                  sea_cli_bake_progress *prog, sea_bake *b, sea_error *err)
{
    const int size = sea_cli_mpi_size();
    bake_rows_ctx c = {w, in, open, failed};
    sea_status st = sea_bake_frame_rows(r, t, view_k, 0, size, b, sea_cli_bake_progress_compute, prog,
                                        rows_gather, &c, err);
    for (int k = 1; k < size; k++)
        while (open[k]) {
            sea_status later = st == SEA_OK ? SEA_OK : SEA_ERR_CANCELLED;
            sea_error dropped;
            if (rows_recv(k, NULL, &later, &dropped) == BAKE_MSG_END) {
                open[k] = false;
                if (st == SEA_OK && later != SEA_OK) {
                    st = later;
                    if (err != NULL)
                        *err = dropped;
                }
            } else {
                const int stop = BAKE_ACK_STOP;
                sea_cli_mpi_send(&stop, sizeof stop, k, BAKE_TAG_ACK);
            }
        }
    return st;
}

/* Rank 0, under MPI: frame f computed elsewhere, whole by rank owner
 * (--frames) or by texel rows among every rank (one frame), each level
 * handed to the writer as it comes; the sensor's image, when the exports
 * project it, rendered here.  A failure before the frame still receives
 * it (the ranks' messages must be matched), writing nothing. */
sea_status sea_cli_bake_frame_mpi(sea_cli_bake_inbox *in, const sea_cli_bake *s,
                                  const sea_view *r, sea_bake_writer *w, int owner, long f,
                                  sea_cli_bake_progress *prog, sea_cli_bake_stats *stats,
                                  sea_error *err)
{
    const double t = sea_bake_options_frame_time(&s->opt, s->sc.time, f);
    sea_bake_stats before, after;
    sea_bake_writer_stats(w, &before);
    const double t0 = sea_cli_seconds();
    sea_error first_err;
    sea_status first = sea_bake_writer_frame_begin(w, f, &first_err);
    sea_image view = {0};
    const bool want_view = sea_bake_writer_wants_view(w);
    if (first == SEA_OK && want_view) {
        const sea_camera *cam = sea_view_camera(r);
        first = sea_image_alloc(cam->width, cam->height, &view, &first_err);
        if (first == SEA_OK)
            first = sea_view_render_frame(r, t, &view, NULL, NULL, &first_err);
    }
    sea_bake b;
    sea_status st;
    if (s->opt.framed) {
        if (first != SEA_OK && err != NULL)
            *err = first_err;
        st = bake_recv_frame(w, in, owner, first, &b, err);
    } else {
        st = bake_rows_frame(w, in, in->sending, r, t, s->opt.view_k, first != SEA_OK, prog, &b,
                             err);
        if (st == SEA_OK) { /* rank 0 computed its rows: its parts */
            stats->parts.waves += b.seconds.waves;
            stats->parts.image += b.seconds.image;
            stats->parts.optics += b.seconds.optics;
            stats->parts.view += b.seconds.view;
        }
    }
    if (first != SEA_OK) {
        if (st == SEA_OK)
            sea_bake_free(&b);
        st = first;
        if (err != NULL)
            *err = first_err;
    }
    /* "maps" is rank 0's computing and waiting for the others: what the
     * writer's files did not take */
    sea_bake_writer_stats(w, &after);
    stats->compute += sea_cli_seconds() - t0 - (after.files - before.files);
    if (st == SEA_OK) {
        st = sea_bake_writer_frame_end(w, &b, want_view ? &view : NULL, err);
        sea_bake_free(&b);
    }
    sea_image_free(&view);
    return st;
}

sea_status sea_cli_bake_inbox_alloc(sea_cli_bake_inbox *in, const sea_cli_bake *s,
                                    const sea_view *r, sea_error *err)
{
    const int size = sea_cli_mpi_size();
    memset(in, 0, sizeof *in);
    in->nmax = 1;
    in->view_k = (size_t)s->opt.view_k;
    if (size == 1)
        return SEA_OK;
    const sea_clip_level *lv;
    const size_t nlev = sea_view_levels(r, &lv), k2 = in->view_k * in->view_k;
    for (size_t l = 0; l < nlev; l++)
        if (!lv[l].low_res && lv[l].nx * lv[l].ny > in->nmax)
            in->nmax = lv[l].nx * lv[l].ny;
    in->moments = malloc(in->nmax * sizeof *in->moments);
    in->optics = malloc(in->nmax * sizeof *in->optics);
    in->view = malloc(k2 * in->nmax * sizeof *in->view);
    in->sending = malloc((size_t)size * sizeof *in->sending);
    for (int k = 0; in->sending != NULL && k < size; k++)
        in->sending[k] = true;
    if (in->moments == NULL || in->optics == NULL || in->view == NULL || in->sending == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the levels of other ranks");
    return SEA_OK;
}

void sea_cli_bake_answer(sea_cli_bake_inbox *in, int owner, sea_status st)
{
    if (owner == 0)
        return;
    const int ack = st == SEA_OK ? BAKE_ACK_GO : BAKE_ACK_STOP;
    sea_cli_mpi_send(&ack, sizeof ack, owner, BAKE_TAG_ACK);
    in->sending[owner] = st == SEA_OK;
}

void sea_cli_bake_inbox_free(sea_cli_bake_inbox *in, const sea_cli_bake *s, sea_bake_writer *w,
                             long f)
{
    const long last = s->opt.framed ? s->opt.last : 0;
    for (; sea_cli_mpi_size() > 1 && in->sending != NULL && f <= last; ++f) {
        const int owner = sea_cli_bake_owner(s, f);
        if (owner == 0 || !in->sending[owner])
            continue;
        sea_bake b;
        sea_error dropped;
        bake_recv_frame(w, in, owner, SEA_ERR_CANCELLED, &b, &dropped);
        const int stop = BAKE_ACK_STOP;
        sea_cli_mpi_send(&stop, sizeof stop, owner, BAKE_TAG_ACK);
        in->sending[owner] = false;
    }
    free(in->moments);
    free(in->optics);
    free(in->view);
    free(in->sending);
    memset(in, 0, sizeof *in);
}
