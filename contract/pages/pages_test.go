package pages_test

import (
	"errors"
	"fmt"
	"testing"

	"photonfarm/contract/pages"
)

// listing serves items in pages of size n, with tokens "p1", "p2", ...
func listing(items []int, n int) (pages.Fetch[int], *[]string) {
	var asked []string
	return func(token string) ([]int, string, error) {
		asked = append(asked, token)
		from := 0
		if token != "" {
			fmt.Sscanf(token, "p%d", &from)
			from *= n
		}
		to := min(from+n, len(items))
		next := ""
		if to < len(items) {
			next = fmt.Sprintf("p%d", to/n)
		}
		return items[from:to], next, nil
	}, &asked
}

func TestAllFollowsEveryPageInOrder(t *testing.T) {
	fetch, asked := listing([]int{1, 2, 3, 4, 5, 6, 7}, 3)
	got, err := pages.All(fetch)
	if err != nil || fmt.Sprint(got) != "[1 2 3 4 5 6 7]" || fmt.Sprint(*asked) != "[ p1 p2]" {
		t.Errorf("All = %v, %v after asking %q", got, err, *asked)
	}
	empty, _ := listing(nil, 3)
	if got, err := pages.All(empty); err != nil || len(got) != 0 {
		t.Errorf("All of nothing = %v, %v", got, err)
	}
}

func TestEachStopsWhenToldOrOnAnError(t *testing.T) {
	fetch, asked := listing([]int{1, 2, 3, 4, 5, 6, 7}, 3)
	var seen []int
	err := pages.Each(fetch, func(v int) (bool, error) {
		seen = append(seen, v)
		return v < 4, nil
	})
	if err != nil || fmt.Sprint(seen) != "[1 2 3 4]" || len(*asked) != 2 {
		t.Errorf("Each saw %v (%v), asked %q; want it to stop at 4 on the second page", seen, err, *asked)
	}
	boom := errors.New("boom")
	failing := func(string) ([]int, string, error) { return nil, "", boom }
	if _, err := pages.All(pages.Fetch[int](failing)); !errors.Is(err, boom) {
		t.Errorf("All = %v, want the fetch's error", err)
	}
}
