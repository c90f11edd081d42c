package main

import (
	"bytes"
	"encoding/json"
	"fmt"
	"os"
	"path"
	"path/filepath"
	"strings"

	"google.golang.org/protobuf/encoding/protojson"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// vectorDir is the folder of the scene vectors, from the repository's root.
const vectorDir = "tests/vectors/scenes"

// Vectors returns the files the generator makes, by path from the repository's root (at
// root): a vector for every case of refused and accepted and for every scene file of
// scenes/ and scenes/stiff/, and the cube mesh they name.
func Vectors(root string) (map[string][]byte, error) {
	files := map[string][]byte{cubeFile: []byte(cubeOBJ)}
	add := func(name string, vec *pb.SceneVector) error {
		file := path.Join(vectorDir, name+".json")
		if _, dup := files[file]; dup {
			return fmt.Errorf("two vectors are called %s", name)
		}
		data, err := marshal(vec)
		files[file] = data
		return err
	}
	for _, c := range append(append([]vectorCase(nil), refused...), accepted...) {
		s := base()
		c.mutate(s)
		vec := &pb.SceneVector{Description: describe(c), Scene: s, RefusedField: c.refused, Grow: c.grow, Assets: map[string]string{}}
		for _, f := range scene.Files(s) {
			if f.Kind == scene.MeshFile && f.Digest == rules.DigestOf([]byte(cubeOBJ)) {
				vec.Assets[f.Digest] = cubeAsset
			}
		}
		if err := add(c.name, vec); err != nil {
			return nil, err
		}
	}
	scenes, err := sceneFiles(root)
	if err != nil {
		return nil, err
	}
	for name, vec := range scenes {
		if err := add(name, vec); err != nil {
			return nil, err
		}
	}
	return files, nil
}

// sceneFiles returns a vector accepting each scene file in scenes/ and scenes/stiff/, its
// mesh files uploaded (their digests set, and named as assets).
func sceneFiles(root string) (map[string]*pb.SceneVector, error) {
	var paths []string
	for _, pattern := range []string{"scenes/*.json", "scenes/stiff/*.json"} {
		found, err := filepath.Glob(filepath.Join(root, pattern))
		if err != nil {
			return nil, err
		}
		paths = append(paths, found...)
	}
	vectors := map[string]*pb.SceneVector{}
	for _, p := range paths {
		rel, err := filepath.Rel(root, p)
		if err != nil {
			return nil, err
		}
		data, err := os.ReadFile(p)
		if err != nil {
			return nil, err
		}
		s, err := scene.ParseJSON(data)
		if err != nil {
			return nil, fmt.Errorf("%s: %w", rel, err)
		}
		vec := &pb.SceneVector{Description: "accepted: " + filepath.ToSlash(rel) + " as a client submits it", Scene: s, Assets: map[string]string{}}
		for _, sh := range s.GetShapes() {
			m := sh.GetMesh()
			if m == nil {
				continue
			}
			meshFile := filepath.Join(filepath.Dir(rel), m.GetPath())
			mesh, err := os.ReadFile(filepath.Join(root, meshFile))
			if err != nil {
				return nil, fmt.Errorf("%s: %w", rel, err)
			}
			m.Digest = rules.DigestOf(mesh)
			fromVectors, err := filepath.Rel(vectorDir, meshFile)
			if err != nil {
				return nil, err
			}
			vec.Assets[m.Digest] = filepath.ToSlash(fromVectors)
		}
		name := strings.TrimSuffix(strings.ReplaceAll(strings.TrimPrefix(filepath.ToSlash(rel), "scenes/"), "/", "-"), ".json")
		vectors["accept-scene-"+name] = vec
	}
	return vectors, nil
}

// describe says what a case checks, from its name, its field and what it covers.
func describe(c vectorCase) string {
	what := strings.ReplaceAll(c.name[strings.Index(c.name, "-")+1:], "-", " ")
	d := "accepted: " + what
	if c.refused != "" {
		d = "refused at " + c.refused + ": " + what
	}
	if len(c.covers) > 0 {
		d += " (covers " + strings.Join(c.covers, ", ") + ")"
	}
	return d
}

// marshal writes vec in protobuf's canonical JSON, indented by two spaces (protojson's
// own spacing is deliberately unstable), with a final newline.
func marshal(vec *pb.SceneVector) ([]byte, error) {
	compact, err := protojson.Marshal(vec)
	if err != nil {
		return nil, err
	}
	var out bytes.Buffer
	if err := json.Indent(&out, compact, "", "  "); err != nil {
		return nil, err
	}
	out.WriteByte('\n')
	return out.Bytes(), nil
}
