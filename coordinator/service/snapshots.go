package service

import (
	"sync"

	"google.golang.org/protobuf/proto"

	pb "photonfarm/proto/renderfarm/v1"
)

// maxRememberedSnapshots bounds snapshotCache; past it an arbitrary entry is forgotten (and
// looked up in the store again if needed).
const maxRememberedSnapshots = 1024

// snapshotCache remembers each job's photon snapshot artifact, so that leasing a render
// tile does not list the job's tasks every time.
type snapshotCache struct {
	mu sync.Mutex
	m  map[string]*pb.Artifact
}

func (c *snapshotCache) get(jobID string) (*pb.Artifact, bool) {
	c.mu.Lock()
	defer c.mu.Unlock()
	a, ok := c.m[jobID]
	if !ok {
		return nil, false
	}
	return proto.Clone(a).(*pb.Artifact), true
}

func (c *snapshotCache) put(jobID string, a *pb.Artifact) {
	c.mu.Lock()
	defer c.mu.Unlock()
	if c.m == nil {
		c.m = make(map[string]*pb.Artifact)
	}
	if len(c.m) >= maxRememberedSnapshots {
		for k := range c.m {
			delete(c.m, k)
			break
		}
	}
	c.m[jobID] = proto.Clone(a).(*pb.Artifact)
}
