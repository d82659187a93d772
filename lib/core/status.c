#include "brdffit/status.h"
#include "brdffit/version.h"

#define BF_STATUS_TEXT_(name, value, text) case name: return text;
#define BF_STATUS_NAME_(name, value, text) case name: return #name;

const char *brdffit_status_string(brdffit_status status)
{
    switch (status) {
        BRDFFIT_STATUS_LIST(BF_STATUS_TEXT_)
    default: break;
    }
    return "unknown status";
}

const char *brdffit_status_name(brdffit_status status)
{
    switch (status) {
        BRDFFIT_STATUS_LIST(BF_STATUS_NAME_)
    default: break;
    }
    return "BRDFFIT_UNKNOWN";
}

unsigned brdffit_version_number(void)
{
    return BRDFFIT_VERSION_NUMBER;
}

const char *brdffit_version_string(void)
{
    return BRDFFIT_VERSION_STRING;
}
