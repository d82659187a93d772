/* brdffit fit --gltf / --mtlx: the fitted glTF material as a glTF 2.0
 * asset and as a MaterialX document. */
#ifndef BRDFFIT_CLI_EXPORT_GLTF_H
#define BRDFFIT_CLI_EXPORT_GLTF_H

#include "cli.h"

/* The models whose fits can be exported: the glTF BRDF itself, and with
 * the KHR_materials_clearcoat coat. */
#define CLI_GLTF_MODEL "gltf"
#define CLI_GLTF_COAT_MODEL "gltf-clearcoat"

/* Whether `model_name` names one of them. */
int cli_gltf_exportable(const char *model_name);

/* `note`, when not NULL, says where the material comes from (a refit, see
 * cli_export_refit()): the asset carries it as the material's
 * extras.brdffit, the MaterialX document as a comment. */

/* Write `path` (atomically) as a glTF 2.0 JSON asset with an embedded
 * base64 buffer: one pbrMetallicRoughness material holding the fitted
 * baseColor (1 channel: grey; 3 channels: RGB), metallic and roughness of a
 * "gltf" model vector (a "gltf-clearcoat" one adds the KHR_materials_clearcoat
 * extension with its clearcoat and clearcoatRoughness), on a UV sphere of radius 1 (positions, normals,
 * indices) in a one-node scene. `name` names the material and the node.
 * Returns 0, or -1 with msg saying why (a model other than those two, a
 * channel count other than 1 or 3, out of memory, I/O). */
int cli_gltf_export(const char *path, const brdffit_model *model, const double *params,
                    size_t n_channels, const char *name, const char *note, char *msg,
                    size_t msg_size);

/* The shader nodes --mtlx writes (--mtlx-shader). */
#define CLI_MTLX_OPENPBR 1u  /* open_pbr_surface SR_<name>, material M_<name> */
#define CLI_MTLX_STANDARD 2u /* standard_surface SS_<name>, material MS_<name> */

/* export_mtlx.c: write `path` (atomically) as a MaterialX 1.39 document
 * holding the same fitted material as an open_pbr_surface (OpenPBR Surface
 * 1.1) and/or a standard_surface (Autodesk Standard Surface), as `shaders`
 * says (0: the OpenPBR one), named after `name` (made a MaterialX
 * identifier), each with its surfacematerial. Returns 0, or -1 with msg as
 * for cli_gltf_export(). */
int cli_mtlx_export(const char *path, const brdffit_model *model, const double *params,
                    size_t n_channels, const char *name, unsigned shaders, const char *note,
                    char *msg, size_t msg_size);

/* export_refit.c. Whether the fits of `model_name` are exported as they
 * are: the glTF models for both exports (`mtlx` zero: --gltf), the OpenPBR
 * models too for --mtlx (their parameters are open_pbr_surface inputs). */
int cli_export_native(const char *model_name, int mtlx);

/* The model the export refits a fit of any other model with: gltf-clearcoat
 * (--gltf) or openpbr-coat (--mtlx) for a model of two lobes (a name ending
 * in -2 or -coat), gltf or openpbr otherwise. */
const char *cli_export_target(const char *model_name, int mtlx);

typedef struct cli_refit {
    brdffit_model *model; /* the target model (owned) */
    double *params;       /* its fitted vector (owned) */
    double rms, ngan;     /* its error figures on the data */
    double cost;          /* and its cost under the fit's objective */
} cli_refit;

/* Fit model `target` to `grid` with the settings of `fitted` (cap,
 * weighting, clear-coat compensation, objective, threads, iteration limit)
 * by the auto pipeline without start values. Returns 0 with *out filled
 * (free it with cli_refit_free()), or -1 with msg saying why. */
int cli_export_refit(const brdffit_grid *grid, const brdffit_fit *fitted, const char *target,
                     cli_refit *out, char *msg, size_t msg_size);
void cli_refit_free(cli_refit *r);

#endif /* BRDFFIT_CLI_EXPORT_GLTF_H */
