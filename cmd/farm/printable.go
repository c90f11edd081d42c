package main

import (
	"fmt"
	"strings"
	"unicode"
	"unicode/utf8"
)

// printable is s with every character that would act on a terminal rather than show
// written as a Go escape: C0 and C1 controls and DEL (ESC and CSI begin the sequences
// that clear the screen or move the cursor, CR and BS overwrite what was printed, a
// newline or tab forges a line or a column), the Unicode controls that reorder or hide
// text (bidirectional overrides and isolates, zero-width marks), and bytes that are not
// UTF-8. Everything a coordinator sends that came from users or workers (scene and
// artifact names, errors, reasons, ids) goes through it before reaching a terminal;
// nothing is dropped, so what is shown can still be told apart.
func printable(s string) string {
	clean := true
	for _, r := range s {
		if r == utf8.RuneError || unsafeRune(r) {
			clean = false
			break
		}
	}
	if clean {
		return s
	}
	var b strings.Builder
	for i := 0; i < len(s); {
		r, n := utf8.DecodeRuneInString(s[i:])
		switch {
		case r == utf8.RuneError && n <= 1:
			fmt.Fprintf(&b, `\x%02x`, s[i])
		case shortEscapes[r] != "":
			b.WriteString(shortEscapes[r])
		case unsafeRune(r) && r < 0x100:
			fmt.Fprintf(&b, `\x%02x`, r)
		case unsafeRune(r):
			fmt.Fprintf(&b, `\u%04x`, r)
		default:
			b.WriteString(s[i : i+n])
		}
		i += n
	}
	return b.String()
}

// shortEscapes are Go's escapes of the controls that have one.
var shortEscapes = map[rune]string{'\a': `\a`, '\b': `\b`, '\f': `\f`, '\n': `\n`, '\r': `\r`, '\t': `\t`, '\v': `\v`}

// unsafeRune reports whether r acts on a terminal or reorders text instead of showing.
func unsafeRune(r rune) bool {
	return unicode.IsControl(r) || unicode.Is(unicode.Bidi_Control, r) ||
		unicode.In(r, unicode.Cf) && r != '\u00ad' // format characters, but the soft hyphen
}

// oneLine is s (an error, a reason) on one line for a terminal: white space runs, line
// breaks included, become one space, and the rest is printable.
func oneLine(s string) string {
	return printable(strings.Join(strings.Fields(s), " "))
}
