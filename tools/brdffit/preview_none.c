/* Without cairo at build time the command has no --preview. */
#include "cli.h"

int cli_png_available(void)
{
    return 0;
}

void cli_preview_cleanup(void)
{
}

int cli_preview_write(const cli_preview_input *in, const char *path, char *msg,
                      size_t msg_size)
{
    (void)in;
    (void)path;
    cli_format(msg, msg_size, "brdffit was built without cairo: no PNG output");
    return -1;
}

int cli_preview_png(const cli_preview_input *in, cli_buf *out, char *msg, size_t msg_size)
{
    (void)in;
    (void)out;
    cli_format(msg, msg_size, "brdffit was built without cairo: no PNG output");
    return -1;
}
