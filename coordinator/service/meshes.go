package service

import (
	"context"
	"errors"
	"fmt"
	"io"

	"photonfarm/contract/assets"
	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// checkMeshes checks, before anything is stored or queued, every mesh file sc names whose
// blob is in the blob store (contract/assets.CheckOBJ; SubmitJob has made sure they all
// are): a broken one is refused as INVALID_ARGUMENT naming shapes[i].mesh, the file as the
// scene names it (MeshFile.path, else its digest), the line and the reason, e.g.
// "shapes[8].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has
// 3 vertices". A blob is read once per call however many shapes name it, and a blob that
// passed is remembered (blobs never change).
func (s *Service) checkMeshes(ctx context.Context, sc *pb.Scene) error {
	refused := map[string]*assets.Error{}
	for i, sh := range sc.GetShapes() {
		m := sh.GetMesh()
		if m == nil {
			continue
		}
		d := m.GetDigest()
		name := m.GetPath()
		if name == "" {
			name = d
		}
		bad, seen := refused[d]
		if !seen {
			var err error
			if bad, err = s.checkMesh(ctx, d); errs.Is(err, errs.DataLoss) {
				return errs.Field(fmt.Sprintf("shapes[%d].mesh.digest", i), "%s: %v; upload the file again", name, err)
			} else if err != nil {
				return err
			}
			refused[d] = bad
		}
		if bad != nil {
			return errs.Field(fmt.Sprintf("shapes[%d].mesh", i), "%s: %v", name, bad)
		}
	}
	return nil
}

// checkMesh checks the mesh blob digest: nil if it passes or is not in the blob store,
// its *assets.Error if it does not parse, or the error of reading it (errs.DataLoss if
// the stored blob is damaged).
func (s *Service) checkMesh(ctx context.Context, digest string) (*assets.Error, error) {
	if _, ok := s.meshes.get(digest); ok {
		return nil, nil
	}
	if _, err := s.cfg.Blobs.Stat(ctx, digest); errs.Is(err, errs.NotFound) {
		return nil, nil
	}
	open := func() (io.ReadCloser, error) {
		r, _, err := s.cfg.Blobs.Open(ctx, digest)
		return r, err
	}
	mesh, err := assets.CheckOBJ(ctx, open, assets.SceneLimits())
	var bad *assets.Error
	switch {
	case errors.As(err, &bad):
		return bad, nil
	case ctx.Err() != nil:
		return nil, ctx.Err()
	case errs.Is(err, errs.DataLoss):
		return nil, err
	case err != nil:
		return nil, errs.Wrap(errs.Internal, err, "check mesh "+digest)
	}
	s.meshes.put(digest, mesh)
	return nil, nil
}
