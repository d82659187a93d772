/* Status codes, their strings, and the version functions. */
#include <stdio.h>
#include <string.h>

#include "test_support.h"

static void test_status_values_are_fixed(void **state)
{
    (void)state;
    /* These numbers are part of the ABI and must never change. */
    assert_int_equal(BRDFFIT_OK, 0);
    assert_int_equal(BRDFFIT_E_INVALID_ARGUMENT, 1);
    assert_int_equal(BRDFFIT_E_OUT_OF_MEMORY, 2);
    assert_int_equal(BRDFFIT_E_PARSE, 4);
    assert_int_equal(BRDFFIT_E_NOT_READY, 18);
}

static void test_status_strings(void **state)
{
    int s;
    (void)state;
    assert_string_equal(brdffit_status_string(BRDFFIT_OK), "success");
    assert_string_equal(brdffit_status_name(BRDFFIT_E_PARSE), "BRDFFIT_E_PARSE");
    for (s = 0; s < BRDFFIT_STATUS_MAX_; s++) {
        assert_non_null(brdffit_status_string((brdffit_status)s));
        assert_string_not_equal(brdffit_status_string((brdffit_status)s), "unknown status");
        assert_int_equal(strncmp(brdffit_status_name((brdffit_status)s), "BRDFFIT_", 8), 0);
    }
    assert_string_equal(brdffit_status_string((brdffit_status)9999), "unknown status");
    assert_string_equal(brdffit_status_name((brdffit_status)-1), "BRDFFIT_UNKNOWN");
}

static void test_version(void **state)
{
    char buf[32];
    (void)state;
    assert_int_equal(brdffit_version_number(), BRDFFIT_VERSION_NUMBER);
    assert_string_equal(brdffit_version_string(), BRDFFIT_VERSION_STRING);
    snprintf(buf, sizeof buf, "%d.%d.%d", BRDFFIT_VERSION_MAJOR, BRDFFIT_VERSION_MINOR,
             BRDFFIT_VERSION_PATCH);
    assert_string_equal(buf, BRDFFIT_VERSION_STRING);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_values_are_fixed),
        cmocka_unit_test(test_status_strings),
        cmocka_unit_test(test_version),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
