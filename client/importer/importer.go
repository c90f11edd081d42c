// Package importer turns the scenes people have into the farm's: glTF 2.0 (.gltf with
// external or embedded buffers and images, .glb) and Wavefront OBJ with its MTL files.
// It writes a scene file's worth of data into a folder: the scene (renderfarm.v1.Scene)
// naming its meshes and images by path, the meshes as farm mesh files
// (docs/mesh-format.md) and the images as they came. Nothing is inlined as JSON arrays;
// a mesh that several nodes use is written once and placed by several instances.
//
// Everything read is untrusted: a model's files must lie in its folder and be regular
// files within the contract's asset size; accessors are checked against their buffers
// before they are read; node hierarchies are walked without recursion, at most
// MaxNodeDepth deep; a problem is an error naming the file and what is wrong. What the
// farm does not use (animations, skins, morph targets, occlusion maps, optional
// extensions it does not know) is listed in Result.Skipped.
package importer

import (
	"context"
	"fmt"
	"os"
	"path/filepath"
	"strings"

	pb "photonfarm/proto/renderfarm/v1"
)

// MaxNodeDepth bounds how deep a glTF node hierarchy may nest.
const MaxNodeDepth = 256

// Options say how to render what is imported.
type Options struct {
	// Width of the film in pixels; the height follows the camera's aspect ratio (4:3
	// without one) unless Height is set.
	Width, Height uint32
	// Environment, if set, is an equirectangular image (a path) that lights the scene and
	// that rays leaving it see: glTF and OBJ have no such thing.
	Environment string
}

// Result is what Import made.
type Result struct {
	Scene *pb.Scene
	// Wrote lists the files written, relative to the output folder.
	Wrote []string
	// Skipped says what the model has that the farm leaves out, and why.
	Skipped []string
	// Chose says what Import decided where the model says nothing (a camera framing the
	// model, a sky when the model has no light).
	Chose []string
}

// Import reads the model at src and writes its meshes and images into out (created if
// needed); the returned scene names them by paths relative to out, so that a scene file
// written there (WriteScene) reads back as is.
func Import(ctx context.Context, src, out string, opt Options) (*Result, error) {
	if opt.Width == 0 {
		opt.Width = 640
	}
	if err := os.MkdirAll(out, 0o755); err != nil {
		return nil, err
	}
	w := &writer{dir: out, names: map[string]bool{}}
	var r *Result
	var err error
	switch strings.ToLower(filepath.Ext(src)) {
	case ".gltf", ".glb":
		r, err = importGLTF(ctx, src, w, opt)
	case ".obj":
		r, err = importOBJ(ctx, src, w, opt)
	default:
		return nil, fmt.Errorf("%s: not a model this farm imports (.gltf, .glb or .obj)", src)
	}
	if err != nil {
		return nil, fmt.Errorf("%s: %w", src, err)
	}
	r.Wrote = w.wrote
	return r, nil
}

// environment adds the equirectangular image at path as the scene's environment.
func (b *build) environment(w *writer, path string) error {
	data, err := ReadModelFile(filepath.Dir(path), filepath.Base(path))
	if err != nil {
		return fmt.Errorf("environment: %v", err)
	}
	t, err := checkImage(data)
	if err != nil {
		return fmt.Errorf("environment %s: %v", path, err)
	}
	rel, err := w.file("textures", "environment", "."+extensionOf(t.Format), data)
	if err != nil {
		return err
	}
	const name = "environment"
	b.scene.Textures = append(b.scene.Textures, &pb.Texture{Name: name, Path: rel})
	b.scene.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: name}}
	return nil
}
