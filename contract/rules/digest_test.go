package rules_test

import (
	"strings"
	"testing"

	"photonfarm/contract/rules"
)

func TestDigestOfKnownContent(t *testing.T) {
	// sha256("hello"), as `printf hello | sha256sum` prints it.
	const hello = "sha256:2cf24dba5fb0a30e26e83b2ac5b9e29e1b161e5c1fa7425e73043362938b9824"
	if got := rules.DigestOf([]byte("hello")); got != hello {
		t.Errorf("DigestOf(hello) = %s, want %s", got, hello)
	}
	h := rules.NewDigestHash()
	h.Write([]byte("hel"))
	h.Write([]byte("lo"))
	if got := rules.DigestSum(h); got != hello {
		t.Errorf("DigestSum of hello streamed in two writes = %s, want %s", got, hello)
	}
}

func TestValidDigest(t *testing.T) {
	for _, tc := range []struct {
		d    string
		want bool
	}{
		{rules.DigestOf(nil), true},
		{"sha256:" + strings.Repeat("0", 64), true},
		{"sha256:" + strings.Repeat("0", 63), false},
		{"sha256:" + strings.Repeat("0", 65), false},
		{"sha256:" + strings.Repeat("A", 64), false},
		{"md5:" + strings.Repeat("0", 64), false},
		{"sha256:../../etc/passwd", false},
		{"", false},
	} {
		if got := rules.ValidDigest(tc.d); got != tc.want {
			t.Errorf("ValidDigest(%q) = %v, want %v", tc.d, got, tc.want)
		}
	}
}
