/* PNG output with libpng, written atomically. Without libpng the command
 * is built without --preview. */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#if defined(BRDFFIT_CLI_PNG)
#include <png.h>

int cli_png_available(void)
{
    return 1;
}

typedef struct png_job {
    const cli_picture *pic;
    const char *description;
    png_bytep *rows;
    char *error; /* libpng's last error message */
    size_t error_size;
} png_job;

static void on_error(png_structp png, png_const_charp text)
{
    png_job *job = png_get_error_ptr(png);
    cli_format(job->error, job->error_size, "libpng: %s", text);
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp text)
{
    (void)png;
    (void)text; /* warnings do not make the file unusable */
}

static void set_header(png_structp png, png_infop info, const png_job *job)
{
    png_text text[2];
    png_set_IHDR(png, info, (png_uint_32)job->pic->width, (png_uint_32)job->pic->height, 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    memset(text, 0, sizeof text);
    text[0].compression = PNG_TEXT_COMPRESSION_NONE;
    text[0].key = (png_charp) "Software";
    text[0].text = (png_charp) "brdffit " BRDFFIT_CLI_VERSION;
    text[1].compression = PNG_TEXT_COMPRESSION_NONE;
    text[1].key = (png_charp) "Description";
    text[1].text = (png_charp)job->description;
    png_set_text(png, info, text, 2);
}

/* Everything that libpng may long-jump out of lives in this function and
 * is set up before setjmp. */
static int encode(FILE *f, png_job *job)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, job, on_error, on_warning);
    png_infop info = png != NULL ? png_create_info_struct(png) : NULL;
    if (png == NULL || info == NULL) {
        cli_format(job->error, job->error_size, "libpng: out of memory");
        png_destroy_write_struct(&png, NULL);
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return -1;
    }
    png_init_io(png, f);
    set_header(png, info, job);
    png_write_info(png, info);
    png_write_image(png, job->rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return 0;
}

static int write_png(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    png_job *job = ctx;
    job->error = msg;
    job->error_size = msg_size;
    return encode(f, job);
}

int cli_png_write(const char *path, const cli_picture *pic, const char *description, char *msg,
                  size_t msg_size)
{
    png_job job;
    size_t y;
    int rc;
    if (pic->width == 0 || pic->height == 0 || pic->width > 0x7fffffff ||
        pic->height > 0x7fffffff) {
        cli_format(msg, msg_size, "picture size %zu x %zu cannot be written", pic->width,
                   pic->height);
        return -1;
    }
    job.pic = pic;
    job.description = description;
    job.rows = malloc(pic->height * sizeof(png_bytep));
    if (job.rows == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    for (y = 0; y < pic->height; y++) job.rows[y] = pic->pixels + y * 3 * pic->width;
    rc = cli_write_atomic(path, write_png, &job, msg, msg_size);
    free(job.rows);
    return rc;
}

#else /* no libpng */

int cli_png_available(void)
{
    return 0;
}

int cli_png_write(const char *path, const cli_picture *pic, const char *description, char *msg,
                  size_t msg_size)
{
    (void)path;
    (void)pic;
    (void)description;
    cli_format(msg, msg_size, "brdffit was built without libpng: no PNG output");
    return -1;
}

#endif
