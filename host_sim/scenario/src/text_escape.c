/* Terminal-safe text for messages (sim/text_escape.h). */
#include "sim/text_escape.h"

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* The length of the valid UTF-8 sequence at s (2..4 bytes) and its code
 * point, or 0 when s does not start one (lone continuation byte, overlong
 * form, surrogate, above U+10FFFF, truncated). */
static size_t utf8_sequence(const unsigned char *s, uint32_t *cp)
{
    size_t n;
    uint32_t min;
    if (s[0] >= 0xc2u && s[0] <= 0xdfu) {
        n = 2;
        min = 0x80u;
        *cp = s[0] & 0x1fu;
    } else if (s[0] >= 0xe0u && s[0] <= 0xefu) {
        n = 3;
        min = 0x800u;
        *cp = s[0] & 0x0fu;
    } else if (s[0] >= 0xf0u && s[0] <= 0xf4u) {
        n = 4;
        min = 0x10000u;
        *cp = s[0] & 0x07u;
    } else {
        return 0;
    }
    for (size_t i = 1; i < n; i++) {
        if ((s[i] & 0xc0u) != 0x80u) {
            return 0; /* also stops at the terminating NUL */
        }
        *cp = (*cp << 6) | (s[i] & 0x3fu);
    }
    const bool surrogate = *cp >= 0xd800u && *cp <= 0xdfffu;
    return (*cp < min || *cp > 0x10ffffu || surrogate) ? 0 : n;
}

/* Code points a terminal does not show as one harmless character. */
static bool unsafe_code_point(uint32_t cp)
{
    return cp < 0xa0u ||                       /* C1 controls */
           (cp >= 0x200eu && cp <= 0x200fu) || /* LRM, RLM */
           (cp >= 0x2028u && cp <= 0x202eu) || /* separators, embeddings */
           (cp >= 0x2066u && cp <= 0x2069u);   /* isolates */
}

/* Append piece (len bytes) to out when it fits whole; count it always. */
static void put(char *out, size_t size, size_t *used, size_t *need, const char *piece, size_t len)
{
    if (*used == *need && *need + len < size) {
        memcpy(out + *used, piece, len);
        *used += len;
    }
    *need += len;
}

static void put_hex(char *out, size_t size, size_t *used, size_t *need, unsigned char byte)
{
    char hex[5];
    snprintf(hex, sizeof(hex), "\\x%02x", (unsigned)byte);
    put(out, size, used, need, hex, 4);
}

size_t text_escape(const char *in, char *out, size_t size)
{
    const unsigned char *s = (const unsigned char *)in;
    size_t used = 0; /* bytes written to out */
    size_t need = 0; /* bytes the whole escaped text needs */
    while (*s != '\0') {
        uint32_t cp = 0;
        const size_t seq = *s >= 0x80u ? utf8_sequence(s, &cp) : 0;
        size_t n = 1;
        if (*s == '\n' || *s == '\r' || *s == '\t') {
            const char esc[2] = { '\\', *s == '\n' ? 'n' : (*s == '\r' ? 'r' : 't') };
            put(out, size, &used, &need, esc, 2);
        } else if (*s >= 0x20u && *s < 0x7fu) {
            put(out, size, &used, &need, (const char *)s, 1);
        } else if (seq > 0 && !unsafe_code_point(cp)) {
            put(out, size, &used, &need, (const char *)s, seq);
            n = seq;
        } else {
            n = seq > 0 ? seq : 1; /* an unsafe sequence: every byte of it */
            for (size_t i = 0; i < n; i++) {
                put_hex(out, size, &used, &need, s[i]);
            }
        }
        s += n;
    }
    if (size > 0) {
        out[used] = '\0';
    }
    return need;
}
