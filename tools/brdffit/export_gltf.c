/* brdffit fit --gltf: a glTF 2.0 asset (JSON, buffer embedded as a base64
 * data URI) with the fitted material on a UV sphere, so that any glTF
 * viewer shows it. The layout follows the glTF 2.0 specification (The
 * Khronos Group): one buffer holding float positions, float normals and
 * unsigned short triangle indices, one buffer view and one accessor each,
 * one mesh, node, scene and material. docs/cli.md describes the file. */
#include "export_gltf.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* Sphere resolution: rings from pole to pole and segments around. */
#define STACKS 32
#define SLICES 64
#define N_VERTS ((STACKS + 1) * (SLICES + 1))
/* Two triangles per quad, one in the quads touching a pole. */
#define N_INDICES (SLICES * (2 * (STACKS - 2) + 2) * 3)

/* glTF constants (componentType, bufferView target, primitive mode). */
#define GL_FLOAT 5126
#define GL_UNSIGNED_SHORT 5123
#define GL_ARRAY_BUFFER 34962
#define GL_ELEMENT_ARRAY_BUFFER 34963
#define GL_TRIANGLES 4

typedef struct material {
    double base[3], metallic, roughness;
    int coated; /* KHR_materials_clearcoat: clearcoat, clearcoat_roughness */
    double clearcoat, clearcoat_roughness;
} material;

typedef struct sphere {
    float pos[N_VERTS][3], nrm[N_VERTS][3];
    uint16_t idx[N_INDICES];
    float lo[3], hi[3]; /* bounds of the positions, as stored */
} sphere;

typedef struct gltf_doc {
    const material *mat;
    const sphere *s;
    const char *name, *note; /* note: NULL, or the material's extras.brdffit */
} gltf_doc;

/* --- the material from the fitted vector ------------------------------------ */

static int param_value(const brdffit_model *model, const double *params, size_t nc,
                       const char *name, size_t c, double *out)
{
    size_t k;
    if (brdffit_model_param_find(model, name, &k) != BRDFFIT_OK) return -1;
    *out = params[brdffit_model_vector_index(model, k, c, nc)];
    return 0;
}

int cli_gltf_exportable(const char *model_name)
{
    return strcmp(model_name, CLI_GLTF_MODEL) == 0 || strcmp(model_name, CLI_GLTF_COAT_MODEL) == 0;
}

static int read_material(const brdffit_model *model, const double *params, size_t nc, material *m,
                         char *msg, size_t msg_size)
{
    size_t c;
    if (!cli_gltf_exportable(brdffit_model_name(model))) {
        cli_format(msg, msg_size, "model \"%s\" is not the glTF BRDF (fit with --model %s or %s)",
                   brdffit_model_name(model), CLI_GLTF_MODEL, CLI_GLTF_COAT_MODEL);
        return -1;
    }
    m->coated = strcmp(brdffit_model_name(model), CLI_GLTF_COAT_MODEL) == 0;
    if (m->coated &&
        (param_value(model, params, nc, "clearcoat", 0, &m->clearcoat) != 0 ||
         param_value(model, params, nc, "clearcoatRoughness", 0, &m->clearcoat_roughness) != 0)) {
        cli_format(msg, msg_size, "model \"%s\" lacks a clearcoat parameter", CLI_GLTF_COAT_MODEL);
        return -1;
    }
    if (nc != 1 && nc != 3) {
        cli_format(msg, msg_size, "glTF colours need 1 or 3 channels, the data have %zu", nc);
        return -1;
    }
    for (c = 0; c < 3; c++)
        if (param_value(model, params, nc, "baseColor", nc == 3 ? c : 0, &m->base[c]) != 0) break;
    if (c < 3 || param_value(model, params, nc, "metallic", 0, &m->metallic) != 0 ||
        param_value(model, params, nc, "roughness", 0, &m->roughness) != 0) {
        cli_format(msg, msg_size, "model \"%s\" lacks a glTF parameter", brdffit_model_name(model));
        return -1;
    }
    return 0;
}

/* --- the sphere ----------------------------------------------------------------- */

/* Vertex (i, j): polar angle pi i / STACKS from +y (glTF's up), azimuth
 * 2 pi j / SLICES; the unit position is its own normal. */
static void sphere_vertices(sphere *s)
{
    size_t i, j, q;
    for (q = 0; q < 3; q++) {
        s->lo[q] = HUGE_VALF;
        s->hi[q] = -HUGE_VALF;
    }
    for (i = 0; i <= STACKS; i++) {
        const double t = PI * (double)i / STACKS;
        for (j = 0; j <= SLICES; j++) {
            const double p = 2.0 * PI * (double)j / SLICES;
            const double v[3] = {sin(t) * sin(p), cos(t), sin(t) * cos(p)};
            const size_t k = i * (SLICES + 1) + j;
            for (q = 0; q < 3; q++) {
                s->pos[k][q] = s->nrm[k][q] = (float)v[q];
                if (s->pos[k][q] < s->lo[q]) s->lo[q] = s->pos[k][q];
                if (s->pos[k][q] > s->hi[q]) s->hi[q] = s->pos[k][q];
            }
        }
    }
}

/* Counter-clockwise seen from outside; the triangle of a polar quad that
 * would have two corners on the pole is left out. */
static void sphere_indices(sphere *s)
{
    size_t i, j, n = 0;
    for (i = 0; i < STACKS; i++) {
        for (j = 0; j < SLICES; j++) {
            const uint16_t a = (uint16_t)(i * (SLICES + 1) + j), b = (uint16_t)(a + SLICES + 1);
            const uint16_t c = (uint16_t)(b + 1), d = (uint16_t)(a + 1);
            if (i + 1 < STACKS) {
                s->idx[n++] = a;
                s->idx[n++] = b;
                s->idx[n++] = c;
            }
            if (i > 0) {
                s->idx[n++] = a;
                s->idx[n++] = c;
                s->idx[n++] = d;
            }
        }
    }
}

/* --- the buffer, little-endian, as base64 ------------------------------------ */

#define POS_BYTES (N_VERTS * 12)
#define IDX_BYTES (N_INDICES * 2)
#define BUFFER_BYTES (2 * POS_BYTES + IDX_BYTES)

static void put_u32(unsigned char *p, uint32_t u)
{
    p[0] = (unsigned char)u;
    p[1] = (unsigned char)(u >> 8);
    p[2] = (unsigned char)(u >> 16);
    p[3] = (unsigned char)(u >> 24);
}

static void pack_buffer(const sphere *s, unsigned char *out)
{
    size_t k, q;
    for (k = 0; k < N_VERTS; k++) {
        for (q = 0; q < 3; q++) {
            uint32_t u;
            memcpy(&u, &s->pos[k][q], sizeof u);
            put_u32(out + 12 * k + 4 * q, u);
            memcpy(&u, &s->nrm[k][q], sizeof u);
            put_u32(out + POS_BYTES + 12 * k + 4 * q, u);
        }
    }
    for (k = 0; k < N_INDICES; k++) {
        out[2 * POS_BYTES + 2 * k] = (unsigned char)s->idx[k];
        out[2 * POS_BYTES + 2 * k + 1] = (unsigned char)(s->idx[k] >> 8);
    }
}

static void put_base64(FILE *f, const unsigned char *p, size_t n)
{
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t i;
    for (i = 0; i + 2 < n; i += 3) {
        const uint32_t v = (uint32_t)p[i] << 16 | (uint32_t)p[i + 1] << 8 | p[i + 2];
        fputc(digits[v >> 18], f);
        fputc(digits[(v >> 12) & 63], f);
        fputc(digits[(v >> 6) & 63], f);
        fputc(digits[v & 63], f);
    }
    if (i < n) {
        const uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0);
        fputc(digits[v >> 18], f);
        fputc(digits[(v >> 12) & 63], f);
        fputc(i + 1 < n ? digits[(v >> 6) & 63] : '=', f);
        fputc('=', f);
    }
}

/* --- the JSON --------------------------------------------------------------- */

static void put_vec3(FILE *f, const float v[3])
{
    fprintf(f, "[%.9g, %.9g, %.9g]", (double)v[0], (double)v[1], (double)v[2]);
}

/* `name` and `note` are JSON string literals (note NULL: none). */
static void put_material(FILE *f, const gltf_doc *d, const char *name, const char *note)
{
    fprintf(f, "  \"materials\": [{\"name\": %s, \"pbrMetallicRoughness\": {", name);
    fprintf(f, "\"baseColorFactor\": [%.17g, %.17g, %.17g, 1], ", d->mat->base[0], d->mat->base[1],
            d->mat->base[2]);
    fprintf(f, "\"metallicFactor\": %.17g, \"roughnessFactor\": %.17g}", d->mat->metallic,
            d->mat->roughness);
    if (d->mat->coated)
        fprintf(f,
                ", \"extensions\": {\"KHR_materials_clearcoat\": {\"clearcoatFactor\": %.17g, "
                "\"clearcoatRoughnessFactor\": %.17g}}",
                d->mat->clearcoat, d->mat->clearcoat_roughness);
    if (note != NULL) fprintf(f, ", \"extras\": {\"brdffit\": %s}", note);
    fprintf(f, "}],\n");
    fprintf(f, "  \"nodes\": [{\"name\": %s, \"mesh\": 0}],\n", name);
}

static void put_views(FILE *f, const gltf_doc *d)
{
    fprintf(f, "  \"bufferViews\": [\n");
    fprintf(f, "    {\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": %d, \"target\": %d},\n",
            POS_BYTES, GL_ARRAY_BUFFER);
    fprintf(f, "    {\"buffer\": 0, \"byteOffset\": %d, \"byteLength\": %d, \"target\": %d},\n",
            POS_BYTES, POS_BYTES, GL_ARRAY_BUFFER);
    fprintf(f, "    {\"buffer\": 0, \"byteOffset\": %d, \"byteLength\": %d, \"target\": %d}],\n",
            2 * POS_BYTES, IDX_BYTES, GL_ELEMENT_ARRAY_BUFFER);
    fprintf(f, "  \"accessors\": [\n");
    fprintf(f,
            "    {\"bufferView\": 0, \"componentType\": %d, \"count\": %d, \"type\": \"VEC3\", "
            "\"min\": ",
            GL_FLOAT, N_VERTS);
    put_vec3(f, d->s->lo);
    fprintf(f, ", \"max\": ");
    put_vec3(f, d->s->hi);
    fprintf(f,
            "},\n    {\"bufferView\": 1, \"componentType\": %d, \"count\": %d, "
            "\"type\": \"VEC3\"},\n",
            GL_FLOAT, N_VERTS);
    fprintf(f,
            "    {\"bufferView\": 2, \"componentType\": %d, \"count\": %d, "
            "\"type\": \"SCALAR\"}],\n",
            GL_UNSIGNED_SHORT, N_INDICES);
}

static int write_doc(FILE *f, void *ctx, char *msg, size_t msg_size)
{
    const gltf_doc *d = ctx;
    unsigned char *bytes = malloc(BUFFER_BYTES);
    cli_buf name, note;
    cli_buf_init(&name);
    cli_buf_init(&note);
    cli_buf_json_string(&name, d->name);
    if (d->note != NULL) cli_buf_json_string(&note, d->note);
    if (bytes == NULL || name.failed || note.failed) {
        free(bytes);
        cli_buf_free(&name);
        cli_buf_free(&note);
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    pack_buffer(d->s, bytes);
    fprintf(f, "{\n  \"asset\": {\"version\": \"2.0\", \"generator\": \"brdffit %s\"},\n",
            BRDFFIT_CLI_VERSION);
    if (d->mat->coated) fprintf(f, "  \"extensionsUsed\": [\"KHR_materials_clearcoat\"],\n");
    fprintf(f, "  \"scene\": 0,\n  \"scenes\": [{\"nodes\": [0]}],\n");
    put_material(f, d, name.data, d->note != NULL ? note.data : NULL);
    fprintf(f,
            "  \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, "
            "\"NORMAL\": 1}, \"indices\": 2, \"material\": 0, \"mode\": %d}]}],\n",
            GL_TRIANGLES);
    put_views(f, d);
    fprintf(f,
            "  \"buffers\": [{\"byteLength\": %d, "
            "\"uri\": \"data:application/octet-stream;base64,",
            BUFFER_BYTES);
    put_base64(f, bytes, BUFFER_BYTES);
    fprintf(f, "\"}]\n}\n");
    free(bytes);
    cli_buf_free(&name);
    cli_buf_free(&note);
    return 0;
}

int cli_gltf_export(const char *path, const brdffit_model *model, const double *params,
                    size_t n_channels, const char *name, const char *note, char *msg,
                    size_t msg_size)
{
    material m;
    gltf_doc d;
    sphere *s;
    int rc;
    if (read_material(model, params, n_channels, &m, msg, msg_size) != 0) return -1;
    s = malloc(sizeof *s);
    if (s == NULL) {
        cli_format(msg, msg_size, "out of memory");
        return -1;
    }
    sphere_vertices(s);
    sphere_indices(s);
    d.mat = &m;
    d.s = s;
    d.name = name;
    d.note = note;
    rc = cli_write_atomic(path, write_doc, &d, msg, msg_size);
    free(s);
    return rc;
}
