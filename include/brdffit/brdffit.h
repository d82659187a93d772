/**
 * @file brdffit.h
 * @brief Umbrella header: includes every public header of libbrdffit.
 *
 * libbrdffit fits analytic BRDF models to measured reflectance tables with a
 * weighted Levenberg-Marquardt solver. The data flow is: grid (grid.h,
 * load.h) -> model (model.h) -> optimizer (optim.h) -> fit (fit.h).
 */
#ifndef BRDFFIT_BRDFFIT_H
#define BRDFFIT_BRDFFIT_H

#include "brdffit/alloc.h"
#include "brdffit/export.h"
#include "brdffit/fit.h"
#include "brdffit/grid.h"
#include "brdffit/image.h"
#include "brdffit/load.h"
#include "brdffit/many.h"
#include "brdffit/model.h"
#include "brdffit/optim.h"
#include "brdffit/status.h"
#include "brdffit/version.h"

#endif /* BRDFFIT_BRDFFIT_H */
