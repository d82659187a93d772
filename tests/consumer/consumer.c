/* A program that uses an installed libbrdffit the way a user's would: it
 * checks that the headers and the linked library agree on the version. */
#include <stdio.h>
#include <string.h>

#include <brdffit/brdffit.h>

int main(void)
{
    const char *linked = brdffit_version_string();

    printf("libbrdffit %s (headers %s)\n", linked, BRDFFIT_VERSION_STRING);
#ifdef BRDFFIT_STATIC
    printf("BRDFFIT_STATIC defined\n");
#endif
    if (strcmp(linked, BRDFFIT_VERSION_STRING) != 0) {
        fprintf(stderr, "version mismatch: library %s, headers %s\n", linked,
                BRDFFIT_VERSION_STRING);
        return 1;
    }
    if (brdffit_version_number() != BRDFFIT_VERSION_NUMBER) {
        fprintf(stderr, "version number mismatch: %u\n", brdffit_version_number());
        return 1;
    }
    if (strcmp(brdffit_status_name(BRDFFIT_E_PARSE), "BRDFFIT_E_PARSE") != 0) {
        fprintf(stderr, "brdffit_status_name() is wrong\n");
        return 1;
    }
    return 0;
}
