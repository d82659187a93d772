/* The locale-independent number parser of the CSV loader. */
#include <locale.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "load/load_internal.h"
#include "test_support.h"

static bf_number_kind parse(const char *s, double *v)
{
    return bf_parse_number(s, strlen(s), v);
}

static void expect_number(const char *s, double want)
{
    double v = -1.0;
    if (parse(s, &v) != BF_NUMBER_OK || memcmp(&v, &want, sizeof v) != 0) {
        print_error("'%s' parsed as %.17g, expected %.17g\n", s, v, want);
        fail();
    }
}

static void expect_kind_of(const char *s, bf_number_kind kind)
{
    double v;
    if (parse(s, &v) != kind) {
        print_error("'%s': kind %d, expected %d\n", s, (int)parse(s, &v), (int)kind);
        fail();
    }
}

static void test_syntax(void **state)
{
    static const char *const bad[] = {"x.5",   ".",    "+",   "-",   "1e",  "1e+",  "1.2.3",
                                      "--1",   "0x10", "1,5", "1 2", "e5",  "nanx", "infin",
                                      "1e5.0", "\xff", "1\r", "1d0", "+-1", "1_000"};
    size_t k;
    (void)state;
    expect_number("0", 0.0);
    expect_number("42", 42.0);
    expect_number("+5", 5.0);
    expect_number("-2.5", -2.5);
    expect_number(".5", 0.5);
    expect_number("5.", 5.0);
    expect_number("1e2", 100.0);
    expect_number("1E-3", 0.001);
    expect_number("1.25e+1", 12.5);
    expect_number("  7\t", 7.0);
    expect_number("000123.4500", 123.45);
    expect_number("0.000", 0.0);
    expect_number("-0", -0.0);
    expect_kind_of("", BF_NUMBER_EMPTY);
    expect_kind_of("   ", BF_NUMBER_EMPTY);
    expect_kind_of("nan", BF_NUMBER_NAN);
    expect_kind_of("NaN", BF_NUMBER_NAN);
    expect_kind_of(" NAN ", BF_NUMBER_NAN);
    expect_kind_of("inf", BF_NUMBER_INF);
    expect_kind_of("-Infinity", BF_NUMBER_INF);
    expect_kind_of("1e400", BF_NUMBER_INF);
    expect_kind_of("-1e99999999999999999999", BF_NUMBER_INF);
    for (k = 0; k < sizeof bad / sizeof bad[0]; k++) expect_kind_of(bad[k], BF_NUMBER_MALFORMED);
}

static void test_exponent_extremes(void **state)
{
    char buf[1200];
    (void)state;
    expect_number("1e-99999999999999999999", 0.0);
    expect_number("0e99999999999999", 0.0);
    expect_number("4.9406564584124654e-324", 4.9406564584124654e-324);
    expect_number("2.2250738585072014e-308", 2.2250738585072014e-308);
    expect_number("1.7976931348623157e308", 1.7976931348623157e308);
    expect_kind_of("1.7976931348623159e308", BF_NUMBER_INF);
    expect_number("2e-324", 0.0);
    expect_number("3e-324", 4.9406564584124654e-324);
    /* 0.000...0001e+1000 written with 1000 zeros */
    strcpy(buf, "0.");
    memset(buf + 2, '0', 999);
    strcpy(buf + 1001, "1e1000");
    expect_number(buf, 1.0);
    /* 1 followed by 1000 zeros, times 1e-1000 */
    buf[0] = '1';
    memset(buf + 1, '0', 1000);
    strcpy(buf + 1001, "e-1000");
    expect_number(buf, 1.0);
}

/* Halfway cases need every digit: 2^-1075 * (2k + 1) sits exactly between
 * two doubles; a digit more or less decides the rounding. */
static void test_long_mantissas(void **state)
{
    /* 1 + 2^-53 exactly: halfway between 1 and the next double; ties to even */
    static const char half[] = "1.00000000000000011102230246251565404236316680908203125";
    char buf[2000];
    size_t n;
    (void)state;
    expect_number(half, 1.0);
    /* one more non-zero digit far away rounds up */
    n = strlen(half);
    memcpy(buf, half, n);
    memset(buf + n, '0', 900);
    strcpy(buf + n + 900, "1");
    expect_number(buf, 1.0000000000000002);
    /* the same number with trailing zeros only stays on the tie */
    buf[n + 900] = '0';
    expect_number(buf, 1.0);
    /* just below the tie */
    strcpy(buf, "1.000000000000000111022302462515654042363166809082031249999999999999999");
    expect_number(buf, 1.0);
}

static void test_round_trip_17_digits(void **state)
{
    uint64_t seed = 0x9e3779b97f4a7c15u;
    char buf[64];
    int k;
    (void)state;
    for (k = 0; k < 200000; k++) {
        double x, v;
        uint64_t bits;
        seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
        bits = seed;
        memcpy(&x, &bits, sizeof x);
        if (!isfinite(x)) continue;
        snprintf(buf, sizeof buf, k % 3 == 0 ? "%.17g" : (k % 3 == 1 ? "%.17e" : "%.25g"), x);
        if (parse(buf, &v) != BF_NUMBER_OK || memcmp(&v, &x, sizeof v) != 0) {
            print_error("'%s' -> %.17g\n", buf, v);
            fail();
        }
        /* fewer digits: must agree with the C library's correctly rounded strtod */
        snprintf(buf, sizeof buf, "%.9g", x);
        assert_int_equal(parse(buf, &v), BF_NUMBER_OK);
        x = strtod(buf, NULL);
        assert_memory_equal(&v, &x, sizeof v);
    }
}

static void test_locale_independent(void **state)
{
    static const char *const names[] = {"de_DE.UTF-8", "de_DE.utf8", "de_DE",
                                        "fr_FR.UTF-8", "fr_FR.utf8", "ru_RU.UTF-8"};
    size_t k;
    int found = 0;
    (void)state;
    for (k = 0; k < sizeof names / sizeof names[0] && !found; k++)
        found = setlocale(LC_NUMERIC, names[k]) != NULL;
    if (!found) skip(); /* no locale with a decimal comma installed */
    assert_string_equal(localeconv()->decimal_point, ",");
    expect_number("0.5", 0.5);
    expect_number("1234.0625e-2", 12.340625);
    expect_kind_of("0,5", BF_NUMBER_MALFORMED);
    setlocale(LC_NUMERIC, "C");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_syntax),
        cmocka_unit_test(test_exponent_extremes),
        cmocka_unit_test(test_long_mantissas),
        cmocka_unit_test(test_round_trip_17_digits),
        cmocka_unit_test(test_locale_independent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
