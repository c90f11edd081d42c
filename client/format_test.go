package client

import "testing"

func TestFormatCount(t *testing.T) {
	for _, tc := range []struct {
		n    uint64
		want string
	}{{0, "0"}, {999, "999"}, {1000, "1,000"}, {1200000, "1,200,000"}, {12345678, "12,345,678"}} {
		if got := FormatCount(tc.n); got != tc.want {
			t.Errorf("FormatCount(%d) = %q, want %q", tc.n, got, tc.want)
		}
	}
}

func TestFormatMetric(t *testing.T) {
	v := 0.0123456
	if got := FormatMetric(&v); got != "0.01235" {
		t.Errorf("FormatMetric(%v) = %q, want 0.01235", v, got)
	}
	if got := FormatMetric(nil); got != "-" {
		t.Errorf("FormatMetric(nil) = %q, want -", got)
	}
}
