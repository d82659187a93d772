/* Locale-independent parsing of decimal numbers.
 *
 * The syntax is checked here; the conversion goes through strtod() on a
 * rewritten string of the form "<digits>e<exponent>" that contains no
 * decimal point, so the locale's LC_NUMERIC cannot change the result, and
 * the conversion stays correctly rounded. Mantissas longer than
 * BF_MAX_DIGITS significant digits are cut with a sticky non-zero digit,
 * which keeps the rounding decision intact: every halfway point between
 * two doubles has fewer significant digits than that. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "load/load_internal.h"

#define BF_MAX_DIGITS 800
#define BF_MAX_EXP 1000000000LL

typedef struct mantissa {
    char digits[BF_MAX_DIGITS + 2];
    size_t n;       /* significant digits kept */
    long long exp;  /* value = digits * 10^exp */
    int sticky;     /* a non-zero digit was dropped */
    int seen_digit; /* at least one digit in the mantissa */
} mantissa;

static int is_digit(char c)
{
    return c >= '0' && c <= '9';
}

static int lower(char c)
{
    return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c;
}

static int equals_ci(const char *s, size_t len, const char *word)
{
    size_t k;
    if (strlen(word) != len) return 0;
    for (k = 0; k < len; k++)
        if (lower(s[k]) != word[k]) return 0;
    return 1;
}

static void add_digit(mantissa *m, char d, int fraction)
{
    m->seen_digit = 1;
    if (m->n == 0 && d == '0') { /* leading zero */
        m->exp -= fraction;
        return;
    }
    if (m->n < BF_MAX_DIGITS) {
        m->digits[m->n++] = d;
        m->exp -= fraction;
        return;
    }
    m->sticky |= d != '0';
    m->exp += !fraction;
}

/* Parse the exponent digits after 'e'; returns the position after them,
 * or 0 when malformed. */
static size_t parse_exponent(const char *s, size_t len, size_t p, long long *e)
{
    int neg = 0;
    long long v = 0;
    size_t start;
    if (p < len && (s[p] == '+' || s[p] == '-')) neg = s[p++] == '-';
    start = p;
    for (; p < len && is_digit(s[p]); p++)
        if (v < BF_MAX_EXP) v = v * 10 + (s[p] - '0');
    if (p == start) return 0;
    *e = neg ? -v : v;
    return p;
}

/* Write e in decimal at out (no locale, no printf); returns the length. */
static size_t write_exponent(char *out, long long e)
{
    char tmp[24];
    size_t t = 0, o = 0;
    unsigned long long u = e < 0 ? (unsigned long long)(-e) : (unsigned long long)e;
    if (e < 0) out[o++] = '-';
    do tmp[t++] = (char)('0' + u % 10);
    while ((u /= 10) != 0);
    while (t > 0) out[o++] = tmp[--t];
    out[o] = '\0';
    return o;
}

static double convert(mantissa *m)
{
    char buf[BF_MAX_DIGITS + 32];
    long long top;
    if (m->n == 0) return 0.0;
    if (m->sticky) {
        m->digits[m->n++] = '1';
        m->exp -= 1;
    } else {
        while (m->digits[m->n - 1] == '0') m->n--, m->exp++;
    }
    top = m->exp + (long long)m->n; /* value < 10^top */
    if (top > 310) return HUGE_VAL;
    if (top < -330) return 0.0;
    memcpy(buf, m->digits, m->n);
    buf[m->n] = 'e';
    write_exponent(buf + m->n + 1, m->exp);
    return strtod(buf, NULL);
}

static void trim(const char **s, size_t *len)
{
    while (*len > 0 && ((*s)[0] == ' ' || (*s)[0] == '\t')) (*s)++, (*len)--;
    while (*len > 0 && ((*s)[*len - 1] == ' ' || (*s)[*len - 1] == '\t')) (*len)--;
}

static bf_number_kind parse_mantissa(const char *s, size_t len, mantissa *m)
{
    size_t p = 0;
    for (; p < len && is_digit(s[p]); p++) add_digit(m, s[p], 0);
    if (p < len && s[p] == '.')
        for (p++; p < len && is_digit(s[p]); p++) add_digit(m, s[p], 1);
    if (!m->seen_digit) return BF_NUMBER_MALFORMED;
    if (p < len && (s[p] == 'e' || s[p] == 'E')) {
        long long e = 0;
        p = parse_exponent(s, len, p + 1, &e);
        if (p == 0) return BF_NUMBER_MALFORMED;
        m->exp += e;
    }
    return p == len ? BF_NUMBER_OK : BF_NUMBER_MALFORMED;
}

bf_number_kind bf_parse_number(const char *s, size_t len, double *value)
{
    mantissa m;
    int neg = 0;
    double v;
    *value = 0.0;
    trim(&s, &len);
    if (len == 0) return BF_NUMBER_EMPTY;
    if (s[0] == '+' || s[0] == '-') neg = s[0] == '-', s++, len--;
    if (equals_ci(s, len, "nan")) return BF_NUMBER_NAN;
    if (equals_ci(s, len, "inf") || equals_ci(s, len, "infinity")) {
        *value = neg ? -HUGE_VAL : HUGE_VAL;
        return BF_NUMBER_INF;
    }
    memset(&m, 0, sizeof m);
    if (parse_mantissa(s, len, &m) != BF_NUMBER_OK) return BF_NUMBER_MALFORMED;
    v = convert(&m);
    *value = neg ? -v : v;
    return isinf(v) ? BF_NUMBER_INF : BF_NUMBER_OK;
}
