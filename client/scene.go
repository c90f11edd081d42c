package client

import (
	"context"
	"errors"
	"fmt"
	"io"
	"io/fs"
	"os"
	"path/filepath"
	"strings"

	"photonfarm/contract/assets"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// SceneFile is a scene read from disk, with the mesh files it references resolved,
// checked and hashed but not uploaded yet.
type SceneFile struct {
	// Path is the scene file as given.
	Path string
	// Scene has every mesh's digest set, ready to submit once Meshes are uploaded. A
	// mesh's path stays as the scene file writes it, so that the coordinator's messages
	// name the file as the user knows it; the reference image's path is cleared.
	Scene *pb.Scene
	// Meshes are the distinct files the scene references: its mesh files, then its
	// reference image (progressive.reference.path), if any.
	Meshes []MeshRef
}

// MeshRef is one mesh file a scene references.
type MeshRef struct {
	// Field is the first shape field that names the file ("shapes[3].mesh.path").
	Field string
	// File is the path on disk: relative paths resolved against the scene file's folder,
	// symbolic links resolved (it lies inside the asset root).
	File   string
	Digest string
	Size   int64
}

// A SceneOption changes how ReadSceneFile and LoadSceneFile read a scene.
type SceneOption func(*sceneOptions)

type sceneOptions struct {
	assetRoot string
}

// WithAssetRoot sets the folder that every file a scene names (meshes, the reference
// image) must lie in; by default it is the scene file's folder. A path that leaves it
// (through "..", as an absolute path, or through a symbolic link) is refused.
func WithAssetRoot(dir string) SceneOption {
	return func(o *sceneOptions) { o.assetRoot = dir }
}

// ReadSceneFile parses the scene file at path (protobuf's JSON mapping of
// renderfarm.v1.Scene) and reads the mesh files it references, relative to the scene
// file's folder. Every file it names must lie inside the asset root (WithAssetRoot; by
// default the scene file's folder), symbolic links resolved, and be a regular file of at
// most the contract's max_asset_bytes; each mesh is checked as the coordinator will check
// it (contract/assets), so a broken one fails here, before anything is uploaded. Every
// error that is the file's fault is an *Error with code InvalidArgument naming the field:
// "shapes[3].mesh.path: open meshes/x.obj: no such file or directory", "shapes[8].mesh:
// meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices". The
// rest of the scene is not validated here; the coordinator does that on submit. Reading
// stops with ctx's error when ctx ends.
func ReadSceneFile(ctx context.Context, path string, opts ...SceneOption) (*SceneFile, error) {
	var o sceneOptions
	for _, opt := range opts {
		opt(&o)
	}
	data, err := readSmallFile(path)
	if err != nil {
		return nil, invalid("", err.Error(), err)
	}
	sc, err := scene.ParseJSON(data)
	if err != nil {
		// Named by its file instead of "scene": the user may have many.
		return nil, invalid("", path+": "+strings.TrimPrefix(err.Error(), "scene: "), err)
	}
	sf := &SceneFile{Path: path, Scene: sc}
	dir := filepath.Dir(path)
	if o.assetRoot == "" {
		o.assetRoot = dir
	}
	root, err := newAssetRoot(o.assetRoot)
	if err != nil {
		return nil, err
	}
	seen := map[string]int{} // resolved file -> index in sf.Meshes
	for _, f := range scene.Files(sc) {
		if f.Path == "" {
			continue
		}
		file, err := root.resolve(f.Field+".path", dir, f.Path)
		if err != nil {
			return nil, err
		}
		j, ok := seen[file]
		if !ok {
			digest, size, err := readAsset(ctx, sc, f, file)
			if err != nil {
				return nil, err
			}
			j = len(sf.Meshes)
			seen[file] = j
			sf.Meshes = append(sf.Meshes, MeshRef{Field: f.Field + ".path", File: file, Digest: digest, Size: size})
		}
		digest := sf.Meshes[j].Digest
		if f.Digest != "" && f.Digest != digest {
			return nil, invalid(f.Field+".digest",
				fmt.Sprintf("is %s but the file at path %q has digest %s; set only one of path and digest", f.Digest, f.Path, digest), nil)
		}
		f.SetDigest(digest)
	}
	return sf, nil
}

// assetRoot is the folder a scene's files must stay in: as given, absolute, and with
// symbolic links resolved.
type assetRoot struct {
	abs, resolved string
}

func newAssetRoot(dir string) (*assetRoot, error) {
	abs, err := filepath.Abs(dir)
	if err != nil {
		return nil, invalid("", fmt.Sprintf("asset root %s: %v", dir, err), err)
	}
	resolved, err := filepath.EvalSymlinks(abs)
	if err != nil {
		return nil, invalid("", fmt.Sprintf("asset root: %v", err), err)
	}
	if st, err := os.Stat(resolved); err != nil || !st.IsDir() {
		return nil, invalid("", fmt.Sprintf("asset root %s is not a folder", dir), err)
	}
	return &assetRoot{abs: abs, resolved: resolved}, nil
}

// within reports whether path p is root or lies below it (both absolute and clean).
func within(root, p string) bool {
	rel, err := filepath.Rel(root, p)
	return err == nil && !filepath.IsAbs(rel) && rel != ".." && !strings.HasPrefix(rel, ".."+string(filepath.Separator))
}

// resolve returns the path, symbolic links resolved, of the file a scene names as p,
// relative paths being relative to the scene's folder dir. It refuses, naming field, p and
// the root, a path that leaves the root as written ("..", an absolute path elsewhere) or
// once its symbolic links are followed. A file that does not exist gives the error of
// opening it.
func (r *assetRoot) resolve(field, dir, p string) (string, error) {
	file := p
	if !filepath.IsAbs(file) {
		file = filepath.Join(dir, file)
	}
	abs, err := filepath.Abs(file)
	if err != nil {
		return "", invalid(field, err.Error(), err)
	}
	if !within(r.abs, abs) && !within(r.resolved, abs) {
		return "", invalid(field, fmt.Sprintf("%q is outside the asset root %s (it is %s); move the file into the root or choose a wider root (farm: --asset-root DIR)", p, r.abs, abs), nil)
	}
	resolved, err := filepath.EvalSymlinks(abs)
	if err != nil {
		// Report it as opening the file would, naming the path as the scene does.
		if f, oerr := os.Open(abs); oerr != nil {
			err = oerr
		} else {
			f.Close()
		}
		return "", invalid(field, asWritten(err, p).Error(), err)
	}
	if !within(r.resolved, resolved) {
		return "", invalid(field, fmt.Sprintf("%q leads through a symbolic link to %s, outside the asset root %s; move the file into the root or choose a wider root (farm: --asset-root DIR)", p, resolved, r.resolved), nil)
	}
	return resolved, nil
}

// readAsset checks and hashes the file at file, which the scene names at f: a regular
// file within the contract's size limit (a device such as /dev/zero would never end) that
// contract/assets accepts as what f holds.
func readAsset(ctx context.Context, sc *pb.Scene, f scene.File, file string) (digest string, size int64, err error) {
	lim := assets.SceneLimits()
	digest, size, err = fileDigest(ctx, file, lim.MaxBytes)
	if err != nil {
		if ctx.Err() != nil {
			return "", 0, ctx.Err()
		}
		return "", 0, invalid(f.Field+".path", asWritten(err, f.Path).Error(), err)
	}
	err = assets.CheckFile(ctx, func() (io.ReadCloser, error) { return openRegular(file, lim.MaxBytes) }, f, sc)
	var bad assets.Refusal
	switch {
	case errors.As(err, &bad):
		return "", 0, invalid(f.Field, f.Path+": "+bad.Error(), err)
	case err != nil && ctx.Err() != nil:
		return "", 0, ctx.Err()
	case err != nil:
		return "", 0, invalid(f.Field+".path", asWritten(err, f.Path).Error(), err)
	}
	return digest, size, nil
}

// asWritten names the file in err as the scene does, not as resolved.
func asWritten(err error, written string) error {
	var pe *fs.PathError
	if errors.As(err, &pe) {
		pe.Path = written
	}
	return err
}

// Upload stores the scene's mesh files in the coordinator's blob store (skipping those it
// has already).
func (c *Client) Upload(ctx context.Context, sf *SceneFile) error {
	for _, m := range sf.Meshes {
		digest, err := c.UploadFile(ctx, m.File)
		if err != nil {
			if _, ok := err.(*Error); ok {
				return err
			}
			return invalid(m.Field, err.Error(), err)
		}
		if digest != m.Digest {
			return invalid(m.Field, fmt.Sprintf("file %s changed while being read", m.File), nil)
		}
	}
	return nil
}

// LoadSceneFile reads the scene file at path (see ReadSceneFile for the options, the asset
// root and the checks), uploads the mesh files and reference image it references and
// returns the scene ready to submit: each has its digest set.
func (c *Client) LoadSceneFile(ctx context.Context, path string, opts ...SceneOption) (*pb.Scene, error) {
	sf, err := ReadSceneFile(ctx, path, opts...)
	if err != nil {
		return nil, err
	}
	if err := c.Upload(ctx, sf); err != nil {
		return nil, err
	}
	return sf.Scene, nil
}

// SceneStem is the name of a scene file without folder and extension:
// "scenes/cornell-box.json" gives "cornell-box".
func SceneStem(path string) string {
	base := filepath.Base(path)
	return strings.TrimSuffix(base, filepath.Ext(base))
}
