/* brdffit fit --mtlx: the fitted glTF or OpenPBR material as a MaterialX document with
 * one open_pbr_surface (OpenPBR Surface 1.1, MaterialX 1.39) and/or one
 * standard_surface (Autodesk Standard Surface), each with the
 * surfacematerial that uses it. The mapping, and where OpenPBR renders
 * differently from glTF's BRDF, are in docs/cli.md. */
#include "export_gltf.h"

#include <stdlib.h>
#include <string.h>

typedef struct mtlx_doc {
    double base[3], metallic, roughness, ior;
    int coated;
    double coat, coat_roughness, coat_ior;
    unsigned shaders; /* CLI_MTLX_OPENPBR | CLI_MTLX_STANDARD */
    const char *note; /* NULL, or a comment on where the material comes from */
    char name[128];   /* a MaterialX identifier */
} mtlx_doc;

/* MaterialX names are letters, digits and '_', not starting with a digit. */
static void identifier(const char *text, char *out, size_t size)
{
    size_t i, j = 0;
    if (text[0] >= '0' && text[0] <= '9' && j + 1 < size) out[j++] = '_';
    for (i = 0; text[i] != '\0' && j + 1 < size; i++) {
        const char ch = text[i];
        const int ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                       (ch >= '0' && ch <= '9') || ch == '_';
        out[j++] = ok ? ch : '_';
    }
    if (j == 0 && size > 1) out[j++] = 'm';
    out[j] = '\0';
}

static int value_of(const brdffit_model *model, const double *params, size_t nc, const char *name,
                    size_t c, double *out)
{
    size_t k;
    if (brdffit_model_param_find(model, name, &k) != BRDFFIT_OK) return -1;
    *out = params[brdffit_model_vector_index(model, k, c, nc)];
    return 0;
}

/* An OpenPBR model's fit: its parameters are the inputs (coat_ior is the
 * model's fixed 1.6). */
static int read_openpbr(const brdffit_model *model, const double *params, size_t nc, mtlx_doc *d)
{
    size_t c;
    int bad = 0;
    for (c = 0; c < 3; c++)
        bad |= value_of(model, params, nc, "base_color", nc == 3 ? c : 0, &d->base[c]);
    bad |= value_of(model, params, nc, "base_metalness", 0, &d->metallic);
    bad |= value_of(model, params, nc, "specular_roughness", 0, &d->roughness);
    bad |= value_of(model, params, nc, "specular_ior", 0, &d->ior);
    d->coat = d->coat_roughness = 0.0;
    d->coat_ior = 1.6;
    d->coated = strcmp(brdffit_model_name(model), "openpbr-coat") == 0;
    if (d->coated) {
        bad |= value_of(model, params, nc, "coat_weight", 0, &d->coat);
        bad |= value_of(model, params, nc, "coat_roughness", 0, &d->coat_roughness);
    }
    return bad;
}

static int read_gltf(const brdffit_model *model, const double *params, size_t nc, mtlx_doc *d)
{
    size_t c;
    int bad = 0;
    for (c = 0; c < 3; c++)
        bad |= value_of(model, params, nc, "baseColor", nc == 3 ? c : 0, &d->base[c]);
    bad |= value_of(model, params, nc, "metallic", 0, &d->metallic);
    bad |= value_of(model, params, nc, "roughness", 0, &d->roughness);
    d->ior = d->coat_ior = 1.5; /* glTF's F0 = 0.04, and the coat's */
    d->coat = d->coat_roughness = 0.0;
    d->coated = strcmp(brdffit_model_name(model), CLI_GLTF_COAT_MODEL) == 0;
    if (d->coated) {
        bad |= value_of(model, params, nc, "clearcoat", 0, &d->coat);
        bad |= value_of(model, params, nc, "clearcoatRoughness", 0, &d->coat_roughness);
    }
    return bad;
}

static int read_doc(const brdffit_model *model, const double *params, size_t nc, mtlx_doc *d,
                    char *msg, size_t msg_size)
{
    const char *name = brdffit_model_name(model);
    int bad;
    if (!cli_export_native(name, 1)) {
        cli_format(msg, msg_size, "model \"%s\" is neither the glTF BRDF nor OpenPBR's", name);
        return -1;
    }
    if (nc != 1 && nc != 3) {
        cli_format(msg, msg_size, "MaterialX colours need 1 or 3 channels, the data have %zu", nc);
        return -1;
    }
    bad = cli_gltf_exportable(name) ? read_gltf(model, params, nc, d)
                                    : read_openpbr(model, params, nc, d);
    if (bad) cli_format(msg, msg_size, "model \"%s\" lacks a parameter of its kind", name);
    return bad ? -1 : 0;
}

static void put_float(FILE *f, const char *name, double x)
{
    fprintf(f, "    <input name=\"%s\" type=\"float\" value=\"%.9g\" />\n", name, x);
}

static void put_color(FILE *f, const char *name, const double *rgb)
{
    fprintf(f, "    <input name=\"%s\" type=\"color3\" value=\"%.9g, %.9g, %.9g\" />\n", name,
            rgb[0], rgb[1], rgb[2]);
}

static const double white[3] = {1.0, 1.0, 1.0};

/* OpenPBR Surface 1.1: SR_<name>, and its material M_<name>. */
static void put_openpbr(FILE *f, const mtlx_doc *d)
{
    fprintf(f, "  <open_pbr_surface name=\"SR_%s\" type=\"surfaceshader\">\n", d->name);
    put_float(f, "base_weight", 1.0);
    put_color(f, "base_color", d->base);
    put_float(f, "base_metalness", d->metallic);
    put_float(f, "base_diffuse_roughness", 0.0);
    put_float(f, "specular_weight", 1.0);
    put_color(f, "specular_color", white);
    put_float(f, "specular_roughness", d->roughness);
    put_float(f, "specular_ior", d->ior);
    put_float(f, "coat_weight", d->coated ? d->coat : 0.0);
    if (d->coated) {
        put_color(f, "coat_color", white);
        put_float(f, "coat_roughness", d->coat_roughness);
        put_float(f, "coat_ior", d->coat_ior);
        put_float(f, "coat_darkening", 0.0);
    }
    fprintf(f, "  </open_pbr_surface>\n");
    fprintf(f, "  <surfacematerial name=\"M_%s\" type=\"material\">\n", d->name);
    fprintf(f, "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_%s\" />\n",
            d->name);
    fprintf(f, "  </surfacematerial>\n");
}

/* Autodesk Standard Surface: SS_<name>, and its material MS_<name>. */
static void put_standard(FILE *f, const mtlx_doc *d)
{
    fprintf(f, "  <standard_surface name=\"SS_%s\" type=\"surfaceshader\">\n", d->name);
    put_float(f, "base", 1.0);
    put_color(f, "base_color", d->base);
    put_float(f, "diffuse_roughness", 0.0);
    put_float(f, "metalness", d->metallic);
    put_float(f, "specular", 1.0);
    put_color(f, "specular_color", white);
    put_float(f, "specular_roughness", d->roughness);
    put_float(f, "specular_IOR", d->ior);
    put_float(f, "coat", d->coated ? d->coat : 0.0);
    if (d->coated) {
        put_color(f, "coat_color", white);
        put_float(f, "coat_roughness", d->coat_roughness);
        put_float(f, "coat_IOR", d->coat_ior);
        put_float(f, "coat_affect_color", 0.0);
        put_float(f, "coat_affect_roughness", 0.0);
    }
    fprintf(f, "  </standard_surface>\n");
    fprintf(f, "  <surfacematerial name=\"MS_%s\" type=\"material\">\n", d->name);
    fprintf(f, "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SS_%s\" />\n",
            d->name);
    fprintf(f, "  </surfacematerial>\n");
}

static int write_doc(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    const mtlx_doc *d = ctx;
    (void)msg;
    (void)msg_size;
    const char *p;
    fprintf(f, "<?xml version=\"1.0\"?>\n");
    fprintf(f, "<!-- brdffit %s: a fitted material as MaterialX shaders (docs/cli.md) -->\n",
            BRDFFIT_CLI_VERSION);
    if (d->note != NULL) {
        fputs("<!-- ", f);
        for (p = d->note; *p != '\0'; p++) /* no "--" inside a comment */
            fputc(*p == '-' && p[1] == '-' ? '_' : *p, f);
        fputs(" -->\n", f);
    }
    fprintf(f, "<materialx version=\"1.39\" colorspace=\"lin_rec709\">\n");
    if (d->shaders & CLI_MTLX_OPENPBR) put_openpbr(f, d);
    if (d->shaders & CLI_MTLX_STANDARD) put_standard(f, d);
    fprintf(f, "</materialx>\n");
    return 0;
}

int cli_mtlx_export(const char *path, const brdffit_model *model, const double *params,
                    size_t n_channels, const char *name, unsigned shaders, const char *note,
                    char *msg, size_t msg_size)
{
    mtlx_doc d;
    if (read_doc(model, params, n_channels, &d, msg, msg_size) != 0) return -1;
    d.note = note;
    d.shaders = shaders != 0 ? shaders : CLI_MTLX_OPENPBR;
    identifier(name, d.name, sizeof d.name);
    return cli_write_atomic(path, write_doc, &d, msg, msg_size);
}
