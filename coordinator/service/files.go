package service

import (
	"context"
	"errors"
	"io"

	"photonfarm/contract/assets"
	"photonfarm/contract/scene"
	"photonfarm/coordinator/errs"
	pb "photonfarm/proto/renderfarm/v1"
)

// checkFiles checks, before anything is stored or queued, every file sc names whose blob
// is in the blob store (scene.Files: mesh files and parts, textures, the reference image;
// contract/assets.CheckFile; SubmitJob has made sure they all are): a broken one is
// refused as INVALID_ARGUMENT naming the field that holds it, the file as the scene names
// it (its path, else its digest) and what is wrong, e.g. "shapes[8].mesh:
// meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices". A blob is
// read once per call however many fields name it, and a blob that passed as a kind is
// remembered (blobs never change).
func (s *Service) checkFiles(ctx context.Context, sc *pb.Scene) error {
	type key struct {
		digest string
		kind   scene.FileKind
	}
	refused := map[key]assets.Refusal{}
	for _, f := range scene.Files(sc) {
		k := key{f.Digest, f.Kind}
		bad, seen := refused[k]
		if !seen {
			var err error
			if bad, err = s.checkFile(ctx, f, sc); errs.Is(err, errs.DataLoss) {
				return errs.Field(f.Field+".digest", "%s: %v; upload the file again", fileName(f), err)
			} else if err != nil {
				return err
			}
			refused[k] = bad
		}
		if bad != nil {
			return errs.Field(f.Field, "%s: %v", fileName(f), bad)
		}
	}
	return nil
}

// fileName is f as the scene names it: its path, else its digest.
func fileName(f scene.File) string {
	if f.Path != "" {
		return f.Path
	}
	return f.Digest
}

// checkFile checks the blob of f: nil if it passes or is not in the blob store, its
// assets.Refusal if it breaks the rules, or the error of reading it (errs.DataLoss if the
// stored blob is damaged).
func (s *Service) checkFile(ctx context.Context, f scene.File, sc *pb.Scene) (assets.Refusal, error) {
	// A reference image is checked against the film's size, so it is not remembered alone.
	remember := f.Kind != scene.ReferenceFile
	if _, ok := s.checked.get(checkedKey(f)); ok && remember {
		return nil, nil
	}
	if _, err := s.cfg.Blobs.Stat(ctx, f.Digest); errs.Is(err, errs.NotFound) {
		return nil, nil
	}
	open := func() (io.ReadCloser, error) {
		r, _, err := s.cfg.Blobs.Open(ctx, f.Digest)
		return r, err
	}
	err := assets.CheckFile(ctx, open, f, sc)
	var bad assets.Refusal
	switch {
	case errors.As(err, &bad):
		return bad, nil
	case ctx.Err() != nil:
		return nil, ctx.Err()
	case errs.Is(err, errs.DataLoss):
		return nil, err
	case err != nil:
		return nil, errs.Wrap(errs.Internal, err, "check "+f.Field+" "+f.Digest)
	}
	if remember {
		s.checked.put(checkedKey(f), struct{}{})
	}
	return nil, nil
}

// checkedKey names a blob that passed as a kind of file.
func checkedKey(f scene.File) string { return string(rune('0'+f.Kind)) + f.Digest }
