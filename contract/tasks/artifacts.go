package tasks

import (
	"fmt"

	pb "photonfarm/proto/renderfarm/v1"
)

// ArtifactInfo is what artifact_info declares for a kind.
type ArtifactInfo struct {
	// Name is the kind's Artifact.name: "tile.exr".
	Name string
	// PreviousRound: read by the next round's task of the phase that makes it.
	PreviousRound bool
}

// Artifact returns kind k's artifact_info; it panics for a kind without one, which only a
// broken contract has.
func Artifact(k pb.ArtifactKind) ArtifactInfo {
	info, ok := infoOf[*pb.ArtifactInfo](k, pb.E_ArtifactInfo)
	if !ok {
		panic(fmt.Sprintf("tasks: artifact kind %d declares no artifact_info", k))
	}
	return ArtifactInfo{Name: info.GetName(), PreviousRound: info.GetPreviousRound()}
}

// ArtifactName returns kind k's Artifact.name ("tile.exr").
func ArtifactName(k pb.ArtifactKind) string { return Artifact(k).Name }

// Find returns the artifact of kind k in list, or nil.
func Find(list []*pb.Artifact, k pb.ArtifactKind) *pb.Artifact {
	name := ArtifactName(k)
	for _, a := range list {
		if a.GetName() == name {
			return a
		}
	}
	return nil
}

// Failure is what failure_info declares for a failure kind.
type Failure struct {
	// Permanent: retrying cannot help; the job fails at once and no worker is blamed.
	Permanent bool
	Label     string
	// BlamesWorker: the failed attempt counts toward the worker's blocklist threshold.
	BlamesWorker bool
}

// FailureOf returns kind k's failure_info; an unknown kind is treated as transient.
func FailureOf(k pb.FailureKind) Failure {
	info, ok := infoOf[*pb.FailureInfo](k, pb.E_FailureInfo)
	if !ok {
		return FailureOf(pb.FailureKind_FAILURE_KIND_TRANSIENT)
	}
	return Failure{Permanent: info.GetPermanent(), Label: info.GetLabel(), BlamesWorker: info.GetBlamesWorker()}
}
