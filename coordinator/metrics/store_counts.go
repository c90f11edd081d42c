package metrics

import (
	"context"

	"photonfarm/coordinator/store"
	pb "photonfarm/proto/renderfarm/v1"
)

// countPage is the page size of the scans.
const countPage = 500

// StoreCounts counts jobs by state, and the tasks of jobs that have not ended by state,
// by paging through st. The cost is one pass over the unfinished jobs' tasks per scrape.
func StoreCounts(st store.Store) CountFunc {
	return func(ctx context.Context) (Counts, error) {
		c := Counts{Jobs: map[pb.JobState]int{}, Tasks: map[pb.TaskState]int{}}
		token := ""
		for {
			jobs, next, err := st.ListJobs(ctx, countPage, token)
			if err != nil {
				return Counts{}, err
			}
			for _, j := range jobs {
				c.Jobs[j.GetState()]++
				if store.Ended(j.GetState()) {
					continue
				}
				if err := countTasks(ctx, st, j.GetId(), c.Tasks); err != nil {
					return Counts{}, err
				}
			}
			if next == "" {
				return c, nil
			}
			token = next
		}
	}
}

func countTasks(ctx context.Context, st store.Store, jobID string, into map[pb.TaskState]int) error {
	token := ""
	for {
		tasks, next, err := st.ListTasks(ctx, jobID, countPage, token)
		if err != nil {
			return err
		}
		for _, t := range tasks {
			into[t.GetState()]++
		}
		if next == "" {
			return nil
		}
		token = next
	}
}
