package client

import (
	"context"
	"errors"
	"fmt"
	"io/fs"
	"os"
	"path/filepath"
	"strings"

	"photonfarm/coordinator/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// SceneFile is a scene read from disk, with the mesh files it references resolved and
// hashed but not uploaded yet.
type SceneFile struct {
	// Path is the scene file as given.
	Path string
	// Scene has every mesh's digest set and path cleared, ready to submit once Meshes are
	// uploaded.
	Scene *pb.Scene
	// Meshes are the distinct files the scene references: its mesh files, then its
	// reference image (progressive.reference.path), if any.
	Meshes []MeshRef
}

// MeshRef is one mesh file a scene references.
type MeshRef struct {
	// Field is the first shape field that names the file ("shapes[3].mesh.path").
	Field string
	// File is the path on disk (relative paths resolved against the scene file's folder).
	File   string
	Digest string
	Size   int64
}

// ReadSceneFile parses the scene file at path (protobuf's JSON mapping of
// renderfarm.v1.Scene) and reads the mesh files it references, relative to the scene
// file's folder. Every error that is the file's fault is an *Error with code
// InvalidArgument naming the field: "shapes[3].mesh.path: open meshes/x.obj: no such file
// or directory". The scene is not validated here; the coordinator does that on submit.
func ReadSceneFile(path string) (*SceneFile, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, invalid("", err.Error(), err)
	}
	sc, err := scene.ParseJSON(data)
	if err != nil {
		return nil, invalid("", err.Error(), err)
	}
	sf := &SceneFile{Path: path, Scene: sc}
	dir := filepath.Dir(path)
	seen := map[string]int{} // resolved file -> index in sf.Meshes
	for i, sh := range sc.GetShapes() {
		m := sh.GetMesh()
		if m == nil || m.GetPath() == "" {
			continue
		}
		field := fmt.Sprintf("shapes[%d].mesh", i)
		file := m.GetPath()
		if !filepath.IsAbs(file) {
			file = filepath.Join(dir, file)
		}
		j, ok := seen[file]
		if !ok {
			digest, size, err := fileDigest(file)
			if err != nil {
				// Name the file as the scene does, not as resolved.
				var pe *fs.PathError
				if errors.As(err, &pe) {
					pe.Path = m.GetPath()
				}
				return nil, invalid(field+".path", err.Error(), err)
			}
			j = len(sf.Meshes)
			seen[file] = j
			sf.Meshes = append(sf.Meshes, MeshRef{Field: field + ".path", File: file, Digest: digest, Size: size})
		}
		digest := sf.Meshes[j].Digest
		if d := m.GetDigest(); d != "" && d != digest {
			return nil, invalid(field+".digest",
				fmt.Sprintf("is %s but the file at path %q has digest %s; set only one of path and digest", d, m.GetPath(), digest), nil)
		}
		m.Digest = digest
		m.Path = ""
	}
	if err := sf.resolveReference(dir); err != nil {
		return nil, err
	}
	return sf, nil
}

// resolveReference hashes the reference image a progressive scene names by path (relative
// to the scene file) and sets its digest; the file is uploaded with the meshes.
func (sf *SceneFile) resolveReference(dir string) error {
	ref := sf.Scene.GetProgressive().GetReference()
	if ref.GetPath() == "" {
		return nil
	}
	const field = "progressive.reference"
	file := ref.GetPath()
	if !filepath.IsAbs(file) {
		file = filepath.Join(dir, file)
	}
	digest, size, err := fileDigest(file)
	if err != nil {
		var pe *fs.PathError
		if errors.As(err, &pe) {
			pe.Path = ref.GetPath()
		}
		return invalid(field+".path", err.Error(), err)
	}
	if d := ref.GetDigest(); d != "" && d != digest {
		return invalid(field+".digest",
			fmt.Sprintf("is %s but the file at path %q has digest %s; set only one of path and digest", d, ref.GetPath(), digest), nil)
	}
	sf.Meshes = append(sf.Meshes, MeshRef{Field: field + ".path", File: file, Digest: digest, Size: size})
	ref.Digest = digest
	ref.Path = ""
	return nil
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

// LoadSceneFile reads the scene file at path, uploads the mesh files and reference image
// it references and returns the scene ready to submit: each has its digest set and its
// path cleared.
func (c *Client) LoadSceneFile(ctx context.Context, path string) (*pb.Scene, error) {
	sf, err := ReadSceneFile(path)
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
