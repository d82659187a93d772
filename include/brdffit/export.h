/**
 * @file export.h
 * @brief Symbol visibility macro used by every public declaration.
 *
 * Shared builds compile the library with hidden visibility; only
 * declarations marked ::BRDFFIT_API are exported. Consumers of a static
 * build define @c BRDFFIT_STATIC (the CMake package and the pkg-config file
 * do so for them).
 */
#ifndef BRDFFIT_EXPORT_H
#define BRDFFIT_EXPORT_H

/**
 * @def BRDFFIT_API
 * @brief Marks a function as part of the library's exported interface.
 */
#if defined(BRDFFIT_STATIC)
#define BRDFFIT_API
#elif defined(_WIN32)
#if defined(BRDFFIT_BUILDING)
#define BRDFFIT_API __declspec(dllexport)
#else
#define BRDFFIT_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) && __GNUC__ >= 4
#define BRDFFIT_API __attribute__((visibility("default")))
#else
#define BRDFFIT_API
#endif

#endif /* BRDFFIT_EXPORT_H */
