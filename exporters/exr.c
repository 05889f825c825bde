/* exr.c - single-part scanline OpenEXR files through the OpenEXR C API
 * (libOpenEXRCore), written atomically.
 *
 * Writing.  Everything the caller passes is checked before the file system
 * is touched, so invalid input leaves nothing behind.  The file is then
 * encoded into seabake's marked temporary beside the destination
 * ("<path>.tmp.XXXXXX/<name>", tempfile.c: a later run can prove it stale
 * and remove it), through a custom write callback on our own descriptor:
 * the library's own temporary file mode uses one fixed name per
 * destination, which two writers of the same path would share.  Only when
 * exr_finish() has written the chunk offset table and fsync() and close()
 * succeeded is the file renamed over the destination; any failure removes
 * the temporary.
 *
 * The library prints its errors to stderr unless given a handler; library
 * code must not print, so a silent handler is installed and messages are
 * built from the status code (exr_get_default_error_message) and from errno
 * as seen by our own read and write callbacks.
 *
 * Channels.  An EXR file stores its channels sorted by name and the coding
 * pipelines list them in file order, so buffers are always matched by name.
 * Row 0 of a buffer is scanline y = 0 of the data window, which equals the
 * display window, and EXR counts y downwards: row 0 is the top row. */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <openexr.h>

#include "exr.h"
#include "internal.h"

enum {
    SEA_EXR_SIZE_MAX = 65536,     /* pixels per side */
    SEA_EXR_CHANNELS_MAX = 64,
    SEA_EXR_CHANNEL_NAME_MAX = 31, /* the EXR short-name limit */
    SEA_EXR_ATTR_NAME_MAX = 63
};

/* Largest finite half float; larger values would be stored as infinity. */
static const float SEA_HALF_MAX = 65504.0f;

/* Attributes with a structural meaning: the eight required ones and those
 * of multi-part, tiled and deep files.  A string attribute by one of these
 * names would corrupt the header, and a reader must not report them. */
static const char *const SEA_EXR_RESERVED[] = {
    "channels", "compression", "dataWindow", "displayWindow", "lineOrder",
    "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth",
    "name", "type", "version", "chunkCount", "tiles"
};

static int is_reserved_attr(const char *name)
{
    for (size_t i = 0; i < sizeof SEA_EXR_RESERVED / sizeof SEA_EXR_RESERVED[0]; i++)
        if (strcmp(name, SEA_EXR_RESERVED[i]) == 0)
            return 1;
    return 0;
}

/* 1..max characters, all printable ASCII (space included). */
static int is_valid_name(const char *name, size_t max)
{
    size_t n = 0;
    for (const char *p = name; *p != '\0'; p++, n++)
        if (*p < 0x20 || *p > 0x7e || n >= max)
            return 0;
    return n >= 1;
}

/* Library errors are reported through return codes; without this handler
 * the library would print them on stderr. */
static void silent_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    (void)code;
    (void)msg;
}

/* --------------------------------------------------------------- writing */

/* Our end of the write callback: the temporary file and the first errno. */
typedef struct {
    int fd;
    int err_no;
} write_sink;

/* pwrite() until everything is written: the library asks for absolute
 * offsets and may call from several threads, which pwrite() allows. */
static int64_t sink_write(exr_const_context_t ctxt, void *userdata, const void *buffer,
                          uint64_t sz, uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    write_sink *s = userdata;
    const char *p = buffer;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pwrite(s->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            if (s->err_no == 0)
                s->err_no = n < 0 ? errno : EIO;
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

/* The marked temporary of path (tempfile.c), its data open for writing. */
static sea_status open_temp(const char *path, sea_temp_file *tmp, int *fd_out, sea_error *err)
{
    const int e = sea_temp_open(tmp, path, fd_out);
    if (e != 0)
        return sea_fail(err, e == ENOMEM ? SEA_ERR_NOMEM : SEA_ERR_IO,
                        "cannot create a temporary file next to %s: %s", path, strerror(e));
    return SEA_OK;
}

static sea_status check_write_args(const char *path, int width, int height,
                                   const sea_exr_channel *channels, size_t n_channels,
                                   const sea_exr_attr *attrs, size_t n_attrs,
                                   const sea_exr_options *opt, sea_error *err)
{
    if (path == NULL || path[0] == '\0')
        return sea_fail(err, SEA_ERR_DOMAIN, "EXR output: empty file name");
    if (width < 1 || width > SEA_EXR_SIZE_MAX || height < 1 || height > SEA_EXR_SIZE_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: image size %d x %d outside 1..%d", path, width,
                        height, SEA_EXR_SIZE_MAX);
    if (channels == NULL || n_channels < 1 || n_channels > SEA_EXR_CHANNELS_MAX)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: %zu channels, allowed 1..%d", path,
                        channels == NULL ? (size_t)0 : n_channels, SEA_EXR_CHANNELS_MAX);
    if (opt->pixel != SEA_EXR_FLOAT && opt->pixel != SEA_EXR_HALF)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: unknown pixel type %d", path, (int)opt->pixel);
    if (opt->compression != SEA_EXR_NONE && opt->compression != SEA_EXR_ZIP &&
        opt->compression != SEA_EXR_PIZ)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: unknown compression %d", path,
                        (int)opt->compression);

    for (size_t c = 0; c < n_channels; c++) {
        const char *name = channels[c].name;
        if (name == NULL || !is_valid_name(name, SEA_EXR_CHANNEL_NAME_MAX))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "%s: channel %zu: name '%s' is not 1..%d printable ASCII characters",
                            path, c, name == NULL ? "(null)" : name, SEA_EXR_CHANNEL_NAME_MAX);
        for (size_t d = 0; d < c; d++)
            if (strcmp(channels[d].name, name) == 0)
                return sea_fail(err, SEA_ERR_DOMAIN, "%s: channel name '%s' given twice", path,
                                name);
        if (channels[c].data == NULL)
            return sea_fail(err, SEA_ERR_DOMAIN, "%s: channel '%s' has no data", path, name);
    }

    if (n_attrs > 0 && attrs == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "%s: %zu attributes but no array", path, n_attrs);
    for (size_t a = 0; a < n_attrs; a++) {
        const char *name = attrs[a].name;
        if (name == NULL || !is_valid_name(name, SEA_EXR_ATTR_NAME_MAX))
            return sea_fail(err, SEA_ERR_DOMAIN,
                            "%s: attribute %zu: name '%s' is not 1..%d printable ASCII characters",
                            path, a, name == NULL ? "(null)" : name, SEA_EXR_ATTR_NAME_MAX);
        if (is_reserved_attr(name))
            return sea_fail(err, SEA_ERR_DOMAIN, "%s: attribute name '%s' is reserved by EXR",
                            path, name);
        for (size_t b = 0; b < a; b++)
            if (strcmp(attrs[b].name, name) == 0)
                return sea_fail(err, SEA_ERR_DOMAIN, "%s: attribute '%s' given twice", path,
                                name);
        if (attrs[a].value == NULL)
            return sea_fail(err, SEA_ERR_DOMAIN, "%s: attribute '%s' has no value", path, name);
        if (strlen(attrs[a].value) > INT32_MAX / 2) /* the header stores int32 sizes */
            return sea_fail(err, SEA_ERR_DOMAIN, "%s: attribute '%s' is too long", path, name);
    }

    /* Values last: this is the one pass over every pixel, so cheap checks
     * fail first. */
    for (size_t c = 0; c < n_channels; c++) {
        const float *v = channels[c].data;
        for (int y = 0; y < height; y++, v += width)
            for (int x = 0; x < width; x++) {
                const float f = v[x];
                if (isfinite(f) && (opt->pixel != SEA_EXR_HALF || fabsf(f) <= SEA_HALF_MAX))
                    continue;
                if (isnan(f))
                    return sea_fail(err, SEA_ERR_NUMERIC,
                                    "%s: channel '%s' pixel (%d, %d) is NaN", path,
                                    channels[c].name, x, y);
                if (isinf(f))
                    return sea_fail(err, SEA_ERR_NUMERIC,
                                    "%s: channel '%s' pixel (%d, %d) is %sinf", path,
                                    channels[c].name, x, y, f < 0 ? "-" : "");
                return sea_fail(err, SEA_ERR_NUMERIC,
                                "%s: channel '%s' pixel (%d, %d) = %g is beyond the half-float "
                                "range (|v| <= 65504)",
                                path, channels[c].name, x, y, (double)f);
            }
    }
    return SEA_OK;
}

/* The message for a failed library call: errno from our write callback
 * when it failed (disk full, I/O error), else the library's reason. */
static sea_status exr_write_fail(sea_error *err, const char *path, const char *what,
                                 exr_result_t rv, const write_sink *sink)
{
    if (sink->err_no != 0)
        return sea_fail(err, SEA_ERR_IO, "cannot write %s: %s", path, strerror(sink->err_no));
    return sea_fail(err, SEA_ERR_IO, "cannot write %s: %s: %s", path, what,
                    exr_get_default_error_message(rv));
}

/* zlib's level for ZIP: the fastest.  On the float maps of a bench bake
 * (1024 x 1024 facets, 6 levels, 363 MB compressed) level 1 writes 0.6 %
 * more bytes than zlib's default (6) and takes 8.1 s of the bake's file
 * time instead of 10.8 s. */
enum { SEA_EXR_ZIP_LEVEL = 1 };

/* Chunks per thread in a batch: enough to balance chunks of uneven cost,
 * few enough that a batch's buffers stay small (a 2048-wide RGBA float
 * chunk of 16 lines is 0.5 MB packed). */
enum { SEA_EXR_BATCH_PER_THREAD = 4 };
/* encode_chunk's own failure: the library listed a channel we did not add. */
static const exr_result_t SEA_EXR_UNEXPECTED_CHANNEL = -1;

/* Stores nothing: the chunk is written later, in order, by the caller. */
static exr_result_t keep_chunk(exr_encode_pipeline_t *pipeline)
{
    (void)pipeline;
    return EXR_ERR_SUCCESS;
}

/* Writes a packed (and compressed) chunk; a compressed chunk that is not
 * smaller than its raw bytes is written raw.  A reader takes a chunk whose
 * stored size equals its raw size for an uncompressed one, but
 * OpenEXRCore 3.1's ZIP keeps its output when it is exactly that size (it
 * falls back only when larger): a chunk of nearly incompressible floats (a
 * noisy radiance image) was read back as garbage. */
static exr_result_t write_chunk(exr_context_t ctx, int part, const exr_chunk_info_t *cinfo,
                                const exr_encode_pipeline_t *enc)
{
    const int raw = enc->compressed_buffer != enc->packed_buffer &&
                    enc->compressed_bytes >= enc->packed_bytes;
    return exr_write_scanline_chunk(ctx, part, cinfo->start_y,
                                    raw ? enc->packed_buffer : enc->compressed_buffer,
                                    raw ? enc->packed_bytes : enc->compressed_bytes);
}

/* Packs and compresses one chunk into enc (initialised on first use, *live
 * then set), leaving the bytes to write in enc->compressed_buffer and
 * compressed_bytes.  Safe to call for different chunks from several threads. */
static exr_result_t encode_chunk(exr_context_t ctx, int part, const exr_chunk_info_t *cinfo,
                                 exr_encode_pipeline_t *enc, int *live, int width,
                                 const sea_exr_channel *channels, size_t n_channels)
{
    exr_result_t rv = *live ? exr_encoding_update(ctx, part, cinfo, enc)
                            : exr_encoding_initialize(ctx, part, cinfo, enc);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    const int first = !*live;
    *live = 1;
    for (int16_t k = 0; k < enc->channel_count; k++) {
        exr_coding_channel_info_t *ch = &enc->channels[k];
        const float *src = NULL;
        for (size_t c = 0; c < n_channels && src == NULL; c++)
            if (strcmp(channels[c].name, ch->channel_name) == 0)
                src = channels[c].data;
        if (src == NULL)
            return SEA_EXR_UNEXPECTED_CHANNEL;
        /* Float input whatever the stored type: the packer converts. */
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_bytes_per_element = (int16_t)sizeof(float);
        ch->user_pixel_stride = (int32_t)sizeof(float);
        ch->user_line_stride = (int32_t)(sizeof(float) * (size_t)width);
        ch->encode_from_ptr = (const uint8_t *)(src + (size_t)(cinfo->start_y) * (size_t)width);
    }
    if (first && (rv = exr_encoding_choose_default_routines(ctx, part, enc)) != EXR_ERR_SUCCESS)
        return rv;
    enc->yield_until_ready_fn = NULL;
    enc->write_fn = keep_chunk;
    return exr_encoding_run(ctx, part, enc);
}

/* Header, then every chunk of scanlines.  The caller owns ctx. */
static sea_status encode_image(exr_context_t ctx, const char *path, int width, int height,
                               const sea_exr_channel *channels, size_t n_channels,
                               const sea_exr_attr *attrs, size_t n_attrs,
                               const sea_exr_options *opt, const write_sink *sink,
                               sea_error *err)
{
    static const exr_compression_t comp[] = {
        [SEA_EXR_NONE] = EXR_COMPRESSION_NONE,
        [SEA_EXR_ZIP] = EXR_COMPRESSION_ZIP,
        [SEA_EXR_PIZ] = EXR_COMPRESSION_PIZ,
    };
    const exr_pixel_type_t ptype = opt->pixel == SEA_EXR_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
    exr_result_t rv;
    int part = 0;

    if ((rv = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part)) != EXR_ERR_SUCCESS)
        return exr_write_fail(err, path, "exr_add_part", rv, sink);
    /* Display window = data window = [0,0]-[w-1,h-1], pixel aspect 1,
     * increasing y: what the simple initialiser sets. */
    rv = exr_initialize_required_attr_simple(ctx, part, width, height, comp[opt->compression]);
    if (rv != EXR_ERR_SUCCESS)
        return exr_write_fail(err, path, "exr_initialize_required_attr_simple", rv, sink);
    if (opt->compression == SEA_EXR_ZIP &&
        (rv = exr_set_zip_compression_level(ctx, part, SEA_EXR_ZIP_LEVEL)) != EXR_ERR_SUCCESS)
        return exr_write_fail(err, path, "exr_set_zip_compression_level", rv, sink);
    for (size_t c = 0; c < n_channels; c++) {
        /* Linear: these are data, not colours (only lossy codecs use it). */
        rv = exr_add_channel(ctx, part, channels[c].name, ptype, EXR_PERCEPTUALLY_LINEAR, 1, 1);
        if (rv != EXR_ERR_SUCCESS)
            return exr_write_fail(err, path, "exr_add_channel", rv, sink);
    }
    for (size_t a = 0; a < n_attrs; a++)
        if (strlen(attrs[a].name) > SEA_EXR_CHANNEL_NAME_MAX) {
            /* Names over 31 characters set the long-names flag (EXR 1.7+). */
            if ((rv = exr_set_longname_support(ctx, 1)) != EXR_ERR_SUCCESS)
                return exr_write_fail(err, path, "exr_set_longname_support", rv, sink);
            break;
        }
    for (size_t a = 0; a < n_attrs; a++) {
        rv = exr_attr_set_string(ctx, part, attrs[a].name, attrs[a].value);
        if (rv != EXR_ERR_SUCCESS)
            return exr_write_fail(err, path, "exr_attr_set_string", rv, sink);
    }
    if ((rv = exr_write_header(ctx)) != EXR_ERR_SUCCESS)
        return exr_write_fail(err, path, "exr_write_header", rv, sink);

    int32_t lines = 0;
    if ((rv = exr_get_scanlines_per_chunk(ctx, part, &lines)) != EXR_ERR_SUCCESS || lines < 1)
        return exr_write_fail(err, path, "exr_get_scanlines_per_chunk", rv, sink);

    /* Chunks are packed and compressed in parallel, a batch at a time (one
     * pipeline per chunk of the batch), and written in order by this
     * thread: a scanline file's chunks go out in increasing y.  The
     * library packs under the context's lock and compresses outside it
     * (exr_encoding_run), so the compression, nearly all of the time with
     * ZIP or PIZ, runs on every thread. */
    const int nchunks = (height + lines - 1) / lines;
#ifdef _OPENMP
    const int threads = opt->compression == SEA_EXR_NONE ? 1 : omp_get_max_threads();
#else
    const int threads = 1;
#endif
    const int batch = nchunks < SEA_EXR_BATCH_PER_THREAD * threads
                          ? nchunks
                          : SEA_EXR_BATCH_PER_THREAD * threads;
    exr_encode_pipeline_t *enc = calloc((size_t)batch, sizeof *enc);
    exr_chunk_info_t *cinfo = calloc((size_t)batch, sizeof *cinfo);
    exr_result_t *rc = calloc((size_t)batch, sizeof *rc);
    int *live = calloc((size_t)batch, sizeof *live);
    sea_status st = SEA_OK;
    if (enc == NULL || cinfo == NULL || rc == NULL || live == NULL) {
        st = sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    for (int c0 = 0; c0 < nchunks && st == SEA_OK; c0 += batch) {
        const int nb = nchunks - c0 < batch ? nchunks - c0 : batch;
        for (int k = 0; k < nb; k++) {
            rv = exr_write_scanline_chunk_info(ctx, part, (c0 + k) * lines, &cinfo[k]);
            if (rv != EXR_ERR_SUCCESS) {
                st = exr_write_fail(err, path, "exr_write_scanline_chunk_info", rv, sink);
                goto done;
            }
        }
#pragma omp parallel for schedule(dynamic) num_threads(threads) if (threads > 1)
        for (int k = 0; k < nb; k++)
            rc[k] = encode_chunk(ctx, part, &cinfo[k], &enc[k], &live[k], width, channels,
                                 n_channels);
        for (int k = 0; k < nb && st == SEA_OK; k++) {
            if (rc[k] == SEA_EXR_UNEXPECTED_CHANNEL)
                st = sea_fail(err, SEA_ERR_IO, "cannot write %s: unexpected channel", path);
            else if (rc[k] != EXR_ERR_SUCCESS)
                st = exr_write_fail(err, path, "exr_encoding_run", rc[k], sink);
            else if ((rv = write_chunk(ctx, part, &cinfo[k], &enc[k])) != EXR_ERR_SUCCESS)
                st = exr_write_fail(err, path, "exr_write_scanline_chunk", rv, sink);
        }
    }
done:
    for (int k = 0; live != NULL && k < batch; k++)
        if (live[k])
            exr_encoding_destroy(ctx, &enc[k]);
    free(enc);
    free(cinfo);
    free(rc);
    free(live);
    return st;
}

sea_status sea_exr_write(const char *path, int width, int height, const sea_exr_channel *channels,
                         size_t n_channels, const sea_exr_attr *attrs, size_t n_attrs,
                         const sea_exr_options *opt, sea_error *err)
{
    static const sea_exr_options defaults = { SEA_EXR_FLOAT, SEA_EXR_NONE };
    if (opt == NULL)
        opt = &defaults;
    sea_status st =
        check_write_args(path, width, height, channels, n_channels, attrs, n_attrs, opt, err);
    if (st != SEA_OK)
        return st;

    sea_temp_file tmp;
    write_sink sink = { -1, 0 };
    if ((st = open_temp(path, &tmp, &sink.fd, err)) != SEA_OK)
        return st;

    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = silent_error_handler;
    init.user_data = &sink;
    init.write_fn = sink_write;
    /* With a custom write function the name only labels the context. */
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        st = exr_write_fail(err, path, "exr_start_write", rv, &sink);
        goto fail;
    }
    st = encode_image(ctx, path, width, height, channels, n_channels, attrs, n_attrs, opt, &sink,
                      err);
    if (st != SEA_OK)
        goto fail;
    /* exr_finish writes the chunk offset table: its status matters. */
    rv = exr_finish(&ctx);
    if (rv != EXR_ERR_SUCCESS || sink.err_no != 0) {
        st = exr_write_fail(err, path, "exr_finish", rv, &sink);
        goto fail;
    }
    /* Data on disk before the rename, or a crash could leave an empty file
     * under the final name. */
    if (fsync(sink.fd) != 0) {
        st = sea_fail(err, SEA_ERR_IO, "cannot write %s: %s", path, strerror(errno));
        goto fail;
    }
    /* close() can report a deferred write error (NFS); the descriptor is
     * released either way. */
    if (close(sink.fd) != 0) {
        sink.fd = -1;
        st = sea_fail(err, SEA_ERR_IO, "cannot write %s: %s", path, strerror(errno));
        goto fail;
    }
    sink.fd = -1;
    const int e = sea_temp_commit(&tmp, path);
    if (e != 0)
        return sea_fail(err, SEA_ERR_IO, "cannot write %s: %s", path, strerror(e));
    return SEA_OK;

fail:
    if (ctx != NULL)
        exr_finish(&ctx); /* the file is discarded: its status does not matter */
    if (sink.fd >= 0)
        close(sink.fd);
    sea_temp_abort(&tmp);
    return st;
}

/* --------------------------------------------------------------- reading */

typedef struct {
    int fd;
    int err_no;
} read_source;

/* pread() until sz bytes or the end of the file (a short count there is
 * what the library expects). */
static int64_t source_read(exr_const_context_t ctxt, void *userdata, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    (void)ctxt;
    (void)error_cb;
    read_source *s = userdata;
    char *p = buffer;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pread(s->fd, p + done, (size_t)(sz - done), (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            if (s->err_no == 0)
                s->err_no = errno;
            return -1;
        }
        if (n == 0)
            break;
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

/* The file size lets the library check offsets in the header against it. */
static int64_t source_size(exr_const_context_t ctxt, void *userdata)
{
    (void)ctxt;
    read_source *s = userdata;
    struct stat sb;
    return fstat(s->fd, &sb) == 0 ? (int64_t)sb.st_size : -1;
}

static sea_status exr_read_fail(sea_error *err, const char *path, const char *what,
                                exr_result_t rv, const read_source *src)
{
    if (src->err_no != 0)
        return sea_fail(err, SEA_ERR_IO, "cannot read %s: %s", path, strerror(src->err_no));
    if (what == NULL)
        return sea_fail(err, SEA_ERR_IO, "cannot read %s: %s", path,
                        exr_get_default_error_message(rv));
    return sea_fail(err, SEA_ERR_IO, "cannot read %s: %s: %s", path, what,
                    exr_get_default_error_message(rv));
}

static char *dup_len(const char *s, size_t n)
{
    char *d = malloc(n + 1);
    if (d != NULL) {
        memcpy(d, s, n);
        d[n] = '\0';
    }
    return d;
}

/* Channel list and string attributes into out (sizes already set). */
static sea_status read_header(exr_context_t ctx, const char *path, sea_exr_image *out,
                              const read_source *src, sea_error *err)
{
    const exr_attr_chlist_t *chl = NULL;
    exr_result_t rv = exr_get_channels(ctx, 0, &chl);
    if (rv != EXR_ERR_SUCCESS || chl == NULL)
        return exr_read_fail(err, path, "exr_get_channels", rv, src);
    if (chl->num_channels < 1)
        return sea_fail(err, SEA_ERR_PARSE, "%s: no channels", path);
    size_t n = (size_t)chl->num_channels;
    for (size_t c = 0; c < n; c++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[c];
        if (e->pixel_type != EXR_PIXEL_FLOAT && e->pixel_type != EXR_PIXEL_HALF)
            return sea_fail(err, SEA_ERR_PARSE,
                            "%s: channel '%s' holds unsigned integers; only FLOAT and HALF "
                            "channels are read",
                            path, e->name.str);
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return sea_fail(err, SEA_ERR_PARSE, "%s: channel '%s' is subsampled (%d x %d)", path,
                            e->name.str, e->x_sampling, e->y_sampling);
    }

    size_t npix = (size_t)out->width * (size_t)out->height;
    if ((out->names = calloc(n, sizeof *out->names)) == NULL ||
        (out->data = calloc(n, sizeof *out->data)) == NULL ||
        (out->pixel = calloc(n, sizeof *out->pixel)) == NULL)
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    out->n_channels = n;
    for (size_t c = 0; c < n; c++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[c];
        out->pixel[c] = e->pixel_type == EXR_PIXEL_HALF ? SEA_EXR_HALF : SEA_EXR_FLOAT;
        out->names[c] = dup_len(e->name.str, (size_t)e->name.length);
        out->data[c] = malloc(npix * sizeof(float));
        if (out->names[c] == NULL || out->data[c] == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory for %d x %d pixels", path,
                            out->width, out->height);
    }

    int32_t count = 0;
    if ((rv = exr_get_attribute_count(ctx, 0, &count)) != EXR_ERR_SUCCESS)
        return exr_read_fail(err, path, "exr_get_attribute_count", rv, src);
    if (count > 0 && ((out->attr_names = calloc((size_t)count, sizeof(char *))) == NULL ||
                      (out->attr_values = calloc((size_t)count, sizeof(char *))) == NULL))
        return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    for (int32_t i = 0; i < count; i++) {
        const exr_attribute_t *a = NULL;
        rv = exr_get_attribute_by_index(ctx, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a);
        if (rv != EXR_ERR_SUCCESS || a == NULL)
            return exr_read_fail(err, path, "exr_get_attribute_by_index", rv, src);
        if (a->type != EXR_ATTR_STRING || a->string == NULL || is_reserved_attr(a->name))
            continue;
        size_t k = out->n_attrs;
        out->attr_names[k] = dup_len(a->name, strlen(a->name));
        out->attr_values[k] =
            dup_len(a->string->str != NULL ? a->string->str : "",
                    a->string->str != NULL && a->string->length > 0 ? (size_t)a->string->length
                                                                    : 0);
        /* Counted before the check so that a half-filled pair is freed. */
        out->n_attrs++;
        if (out->attr_names[k] == NULL || out->attr_values[k] == NULL)
            return sea_fail(err, SEA_ERR_NOMEM, "%s: out of memory", path);
    }
    return SEA_OK;
}

/* Every chunk of scanlines, decoded as float into out->data. */
static sea_status decode_image(exr_context_t ctx, const char *path, const exr_attr_box2i_t *dw,
                               sea_exr_image *out, const read_source *src, sea_error *err)
{
    int32_t nchunks = 0, lines = 0;
    exr_result_t rv = exr_get_chunk_count(ctx, 0, &nchunks);
    if (rv != EXR_ERR_SUCCESS)
        return exr_read_fail(err, path, "exr_get_chunk_count", rv, src);
    if ((rv = exr_get_scanlines_per_chunk(ctx, 0, &lines)) != EXR_ERR_SUCCESS || lines < 1)
        return exr_read_fail(err, path, "exr_get_scanlines_per_chunk", rv, src);

    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int dec_live = 0;
    sea_status st = SEA_OK;
    for (int32_t i = 0; i < nchunks; i++) {
        /* The chunk holding scanline y: the file's line order does not
         * matter since chunks are fetched through the offset table. */
        int y = dw->min.y + i * lines;
        exr_chunk_info_t cinfo;
        if ((rv = exr_read_scanline_chunk_info(ctx, 0, y, &cinfo)) != EXR_ERR_SUCCESS) {
            st = exr_read_fail(err, path, "exr_read_scanline_chunk_info", rv, src);
            break;
        }
        rv = dec_live ? exr_decoding_update(ctx, 0, &cinfo, &dec)
                      : exr_decoding_initialize(ctx, 0, &cinfo, &dec);
        if (rv != EXR_ERR_SUCCESS) {
            st = exr_read_fail(err, path,
                               dec_live ? "exr_decoding_update" : "exr_decoding_initialize", rv,
                               src);
            break;
        }
        dec_live = 1;
        size_t row = (size_t)(cinfo.start_y - dw->min.y);
        if (cinfo.start_y < dw->min.y || (int64_t)row + cinfo.height > out->height) {
            st = sea_fail(err, SEA_ERR_IO, "cannot read %s: chunk %d lies outside the image",
                          path, (int)i);
            break;
        }
        for (int16_t k = 0; k < dec.channel_count; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            float *dst = (float *)sea_exr_image_channel(out, ch->channel_name);
            if (dst == NULL) {
                st = sea_fail(err, SEA_ERR_IO, "cannot read %s: unexpected channel '%s'", path,
                              ch->channel_name);
                break;
            }
            /* HALF channels are converted to float by the unpacker. */
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
            ch->user_pixel_stride = (int32_t)sizeof(float);
            ch->user_line_stride = (int32_t)(sizeof(float) * (size_t)out->width);
            ch->decode_to_ptr = (uint8_t *)(dst + row * (size_t)out->width);
        }
        if (st != SEA_OK)
            break;
        if (i == 0 && (rv = exr_decoding_choose_default_routines(ctx, 0, &dec)) !=
                          EXR_ERR_SUCCESS) {
            st = exr_read_fail(err, path, "exr_decoding_choose_default_routines", rv, src);
            break;
        }
        if ((rv = exr_decoding_run(ctx, 0, &dec)) != EXR_ERR_SUCCESS) {
            st = exr_read_fail(err, path, "exr_decoding_run", rv, src);
            break;
        }
    }
    if (dec_live)
        exr_decoding_destroy(ctx, &dec);
    return st;
}

sea_status sea_exr_read(const char *path, sea_exr_image *out, sea_error *err)
{
    if (out == NULL)
        return sea_fail(err, SEA_ERR_DOMAIN, "sea_exr_read: no output image");
    memset(out, 0, sizeof *out);
    if (path == NULL || path[0] == '\0')
        return sea_fail(err, SEA_ERR_DOMAIN, "EXR input: empty file name");

    read_source src = { open(path, O_RDONLY | O_CLOEXEC), 0 };
    if (src.fd < 0)
        return sea_fail(err, SEA_ERR_IO, "cannot open %s: %s", path, strerror(errno));

    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = silent_error_handler;
    init.user_data = &src;
    init.read_fn = source_read;
    init.size_fn = source_size;
    /* A truncated or damaged file is an error here, not something to patch
     * up by scanning for chunks. */
    init.flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE | EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    sea_status st = SEA_OK;
    exr_result_t rv = exr_start_read(&ctx, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        /* The library's message says what is wrong with the header. */
        st = exr_read_fail(err, path, NULL, rv, &src);
        goto done;
    }

    int parts = 0;
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    exr_attr_box2i_t dw;
    if ((rv = exr_get_count(ctx, &parts)) != EXR_ERR_SUCCESS) {
        st = exr_read_fail(err, path, "exr_get_count", rv, &src);
        goto done;
    }
    if (parts != 1) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: %d parts; only single-part files are read", path,
                      parts);
        goto done;
    }
    if ((rv = exr_get_storage(ctx, 0, &storage)) != EXR_ERR_SUCCESS) {
        st = exr_read_fail(err, path, "exr_get_storage", rv, &src);
        goto done;
    }
    if (storage != EXR_STORAGE_SCANLINE) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: %s storage; only scanline images are read", path,
                      storage == EXR_STORAGE_TILED ? "tiled" : "deep");
        goto done;
    }
    if ((rv = exr_get_data_window(ctx, 0, &dw)) != EXR_ERR_SUCCESS) {
        st = exr_read_fail(err, path, "exr_get_data_window", rv, &src);
        goto done;
    }
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    if (w < 1 || h < 1 || w > INT32_MAX || h > INT32_MAX) {
        st = sea_fail(err, SEA_ERR_PARSE, "%s: invalid data window", path);
        goto done;
    }
    out->width = (int)w;
    out->height = (int)h;
    if ((st = read_header(ctx, path, out, &src, err)) != SEA_OK)
        goto done;
    st = decode_image(ctx, path, &dw, out, &src, err);

done:
    if (ctx != NULL)
        exr_finish(&ctx);
    close(src.fd);
    if (st != SEA_OK)
        sea_exr_image_free(out);
    return st;
}

const float *sea_exr_image_channel(const sea_exr_image *img, const char *name)
{
    if (img == NULL || name == NULL)
        return NULL;
    for (size_t c = 0; c < img->n_channels; c++)
        if (img->names[c] != NULL && strcmp(img->names[c], name) == 0)
            return img->data[c];
    return NULL;
}

const char *sea_exr_image_attr(const sea_exr_image *img, const char *name)
{
    if (img == NULL || name == NULL)
        return NULL;
    for (size_t a = 0; a < img->n_attrs; a++)
        if (img->attr_names[a] != NULL && strcmp(img->attr_names[a], name) == 0)
            return img->attr_values[a];
    return NULL;
}

void sea_exr_image_free(sea_exr_image *img)
{
    if (img == NULL)
        return;
    for (size_t c = 0; c < img->n_channels; c++) {
        if (img->names != NULL)
            free(img->names[c]);
        if (img->data != NULL)
            free(img->data[c]);
    }
    for (size_t a = 0; a < img->n_attrs; a++) {
        free(img->attr_names[a]);
        free(img->attr_values[a]);
    }
    free(img->names);
    free(img->data);
    free(img->pixel);
    free(img->attr_names);
    free(img->attr_values);
    memset(img, 0, sizeof *img);
}
