package tasks

import (
	"fmt"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// Input is a blob a leased task reads, with what it holds in words for people: the
// message of a job that fails because the blob is lost names it so.
type Input struct {
	// What the blob holds: "tile x 32 y 64 of round 1", "the photon snapshot of round 2".
	What     string
	Artifact *pb.Artifact
}

// Inputs lists the blobs a task's filled-in spec names, in the spec's order: a build's
// emission shards, a precompute's, a merge's or a tile's photon snapshot, a merge's
// irradiance shards, a composite's tiles, previous accumulation and reference image. The
// scene, which every task reads, and the mesh files it names are not among them.
func Inputs(t *pb.Task) []Input {
	round := max(t.GetRound(), 1)
	snapshot := fmt.Sprintf("the photon snapshot of round %d", round)
	var in []Input
	add := func(what string, a *pb.Artifact) {
		if a != nil {
			in = append(in, Input{What: what, Artifact: a})
		}
	}
	switch spec := t.GetSpec().(type) {
	case *pb.Task_BuildPhotonMap:
		for _, s := range spec.BuildPhotonMap.GetShards() {
			e := s.GetSpec()
			add(fmt.Sprintf("the %s photon shard of paths %d+%d of round %d", MapName(e.GetMap()), e.GetFirstPhoton(), e.GetPhotonCount(), round), s.GetShard())
		}
	case *pb.Task_PrecomputeIrradiance:
		add(snapshot, spec.PrecomputeIrradiance.GetPhotonSnapshot())
	case *pb.Task_MergeIrradiance:
		add(snapshot, spec.MergeIrradiance.GetPhotonSnapshot())
		for i, a := range spec.MergeIrradiance.GetIrradianceShards() {
			add(fmt.Sprintf("irradiance shard %d of round %d", i, round), a)
		}
	case *pb.Task_RenderTile:
		add(snapshot, spec.RenderTile.GetPhotonSnapshot())
	case *pb.Task_Composite:
		c := spec.Composite
		for _, tile := range c.GetTiles() {
			add(fmt.Sprintf("tile x %d y %d of round %d", tile.GetRect().GetX(), tile.GetRect().GetY(), round), tile.GetTile())
		}
		add(fmt.Sprintf("the accumulation of round %d", round-1), c.GetPreviousAccumulation())
		add("the reference image", c.GetReference())
	}
	return in
}

// MapName is a photon map's name for people: "global", "caustic", "volume".
func MapName(k pb.PhotonMapKind) string {
	return strings.ToLower(strings.TrimPrefix(k.String(), "PHOTON_MAP_KIND_"))
}
