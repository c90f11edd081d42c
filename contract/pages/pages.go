// Package pages follows the contract's paged listings (ListJobs, ListTasks, and the
// store's listings behind them): a page's next token names the page after it, and an
// empty next token ends the listing (job.proto).
package pages

// A Fetch reads the page a token names ("" for the first) and returns its items and the
// next page's token.
type Fetch[T any] func(token string) (items []T, next string, err error)

// Each calls fn with every item of every page in order until fn returns false or an
// error, or the pages end.
func Each[T any](fetch Fetch[T], fn func(T) (more bool, err error)) error {
	token := ""
	for {
		items, next, err := fetch(token)
		if err != nil {
			return err
		}
		for _, it := range items {
			if more, err := fn(it); err != nil || !more {
				return err
			}
		}
		if next == "" {
			return nil
		}
		token = next
	}
}

// All returns the items of every page, in order.
func All[T any](fetch Fetch[T]) ([]T, error) {
	var all []T
	err := Each(fetch, func(it T) (bool, error) {
		all = append(all, it)
		return true, nil
	})
	return all, err
}
