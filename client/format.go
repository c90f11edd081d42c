package client

import "strconv"

// The round metrics (Job.rounds) as the farm's programs print them for people: `farm
// report` and the benchmarks.

// FormatCount writes n with thousands separators: 1,200,000.
func FormatCount(n uint64) string {
	s := strconv.FormatUint(n, 10)
	out := make([]byte, 0, len(s)+len(s)/3)
	for i := range len(s) {
		if i > 0 && (len(s)-i)%3 == 0 {
			out = append(out, ',')
		}
		out = append(out, s[i])
	}
	return string(out)
}

// FormatMetric writes an optional metric (an error estimate, an RMSE) to 4 significant
// digits, or "-" when it is not known.
func FormatMetric(v *float64) string {
	if v == nil {
		return "-"
	}
	return strconv.FormatFloat(*v, 'g', 4, 64)
}

// FormatInterval formats an interval as "low-high" with FormatMetric's digits, or "-" if
// either end is unset.
func FormatInterval(low, high *float64) string {
	if low == nil || high == nil {
		return "-"
	}
	return FormatMetric(low) + "-" + FormatMetric(high)
}
