package assets

import (
	"context"
	"fmt"

	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// CheckFile checks a file that scene s names as f (scene.Files): a mesh file (OBJ or farm
// mesh), a texture (an image within max_texture_pixels), the reference image (an
// OpenEXR image of the film's size), or a medium's farm grid file. It returns nil, a Refusal saying what is wrong, the
// error of reading the file, or ctx's error. The client runs it before uploading and the
// coordinator again on submit.
func CheckFile(ctx context.Context, open Opener, f scene.File, s *pb.Scene) error {
	lim := SceneLimits()
	switch f.Kind {
	case scene.MeshFile:
		_, err := CheckMesh(ctx, open, lim)
		return err
	case scene.GridFile:
		_, err := CheckFarmGrid(ctx, open, SceneGridLimits())
		return err
	case scene.TextureFile:
		_, err := CheckTexture(ctx, open, lim.MaxBytes, MaxTexturePixels())
		return err
	case scene.ReferenceFile:
		t, err := CheckTexture(ctx, open, lim.MaxBytes, MaxTexturePixels())
		if err != nil {
			return err
		}
		w, h := uint64(s.GetFilm().GetWidth()), uint64(s.GetFilm().GetHeight())
		if t.Format != "openexr" || t.Width != w || t.Height != h {
			return &TextureError{fmt.Sprintf("a reference image must be an OpenEXR image of the film's %dx%d pixels, not a %s image of %dx%d", w, h, t.Format, t.Width, t.Height)}
		}
		return nil
	}
	panic(fmt.Sprintf("assets: CheckFile does not know file kind %d", f.Kind))
}
