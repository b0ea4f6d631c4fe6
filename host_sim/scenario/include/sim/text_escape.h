/*
 * Text echoed in messages (scenario keys and values, file names, command
 * line arguments) made safe for a terminal: control characters and bytes
 * that are not printable UTF-8 are shown as escapes, so a key or a file
 * name can neither move the cursor nor change the terminal's state.
 *
 *   \n \r \t            newline, carriage return, tab
 *   \xNN                any other C0 control byte, DEL (0x7f), and every
 *                       byte of an invalid or non-printable UTF-8 sequence
 *                       (C1 controls U+0080-U+009F, the line and paragraph
 *                       separators U+2028-U+2029, the bidirectional
 *                       controls U+200E-U+200F, U+202A-U+202E,
 *                       U+2066-U+2069, surrogates, overlong forms)
 *
 * Printable ASCII and printable UTF-8 characters pass unchanged, and so
 * does the backslash: escaping is idempotent (escaping escaped text
 * changes nothing), so a message may pass through it more than once.
 */
#ifndef SIM_TEXT_ESCAPE_H
#define SIM_TEXT_ESCAPE_H

#include <stddef.h>

/* Escape in into out (size > 0: always NUL-terminated; an escape that does
 * not fit is left out whole, never cut). Returns the length the whole
 * escaped text needs, excluding the NUL (snprintf style). */
size_t text_escape(const char *in, char *out, size_t size);

#endif /* SIM_TEXT_ESCAPE_H */
