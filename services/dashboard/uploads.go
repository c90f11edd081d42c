package dashboard

import (
	"bytes"
	"context"
	"encoding/json"
	"errors"
	"fmt"
	"io"
	"net/http"
	"path"
	"slices"
	"strings"

	"photonfarm/client"
	"photonfarm/contract/assets"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// A browser submits a scene with the files it names (meshes, textures, the reference
// image) in one JSON body, {"scene": {...}, "files": {"NAME": "BASE64"...}}, where NAME is
// the file's name or its path within a chosen folder. A scene that names no file may
// come alone, as the body itself.
type sceneWithFiles struct {
	Scene json.RawMessage   `json:"scene"`
	Files map[string][]byte `json:"files"` // encoding/json reads base64 into []byte
}

// readSubmission parses a submit body into the scene and the files sent with it. A scene
// has no field "scene", so a body with one is the wrapped form.
func readSubmission(data []byte) (*pb.Scene, map[string][]byte, error) {
	var probe map[string]json.RawMessage
	if json.Unmarshal(data, &probe) == nil && probe["scene"] != nil {
		var body sceneWithFiles
		if err := json.Unmarshal(data, &body); err != nil {
			return nil, nil, errorf(http.StatusBadRequest, "want {\"scene\": {...}, \"files\": {\"name\": \"base64\"...}}: "+err.Error())
		}
		data = body.Scene
		sc, err := scene.ParseJSON(data)
		if err != nil {
			return nil, nil, errorf(http.StatusBadRequest, "not a scene file: "+err.Error())
		}
		return sc, body.Files, nil
	}
	sc, err := scene.ParseJSON(data)
	if err != nil {
		return nil, nil, errorf(http.StatusBadRequest, "not a scene file: "+err.Error())
	}
	return sc, nil, nil
}

// matchFile finds the file sent as the scene's path p: the name that is p (cleaned), or
// ends with "/p" (a folder chosen around the scene), or else the only one with p's base
// name (files chosen one by one carry no folder). It says why when none or several match.
func matchFile(files map[string][]byte, field, p string) ([]byte, error) {
	want := path.Clean(strings.TrimPrefix(strings.ReplaceAll(p, `\`, "/"), "./"))
	var exact, byBase []string
	for name := range files {
		n := path.Clean(strings.ReplaceAll(name, `\`, "/"))
		switch {
		case n == want || strings.HasSuffix(n, "/"+want):
			exact = append(exact, name)
		case path.Base(n) == path.Base(want):
			byBase = append(byBase, name)
		}
	}
	for _, found := range [][]string{exact, byBase} {
		switch len(found) {
		case 0:
			continue
		case 1:
			return files[found[0]], nil
		default:
			slices.Sort(found)
			return nil, errorf(http.StatusBadRequest, fmt.Sprintf("%s names the file %s, and several files sent with the scene could be it (%s): choose the folder that holds the scene, so that their paths tell them apart", field, p, strings.Join(found, ", ")))
		}
	}
	sent := make([]string, 0, len(files))
	for name := range files {
		sent = append(sent, name)
	}
	slices.Sort(sent)
	have := "no other file"
	if len(sent) > 0 {
		have = strings.Join(sent, ", ")
	}
	return nil, errorf(http.StatusBadRequest, fmt.Sprintf("%s names the file %s, which was not sent with the scene (sent: %s): choose the scene together with its files, or the folder that holds them", field, p, have))
}

// attachFiles checks each file the scene names by path against its field's rules
// (contract/assets, as the CLI does before uploading), stores it in the blob store and
// sets its digest in the scene. A file named twice is stored once.
func attachFiles(ctx context.Context, blobs *client.Client, sc *pb.Scene, files map[string][]byte) error {
	stored := map[string]string{} // path -> digest
	for _, f := range scene.Files(sc) {
		if f.Path == "" || f.Digest != "" {
			continue
		}
		if d, ok := stored[f.Path]; ok {
			f.SetDigest(d)
			continue
		}
		data, err := matchFile(files, f.Field, f.Path)
		if err != nil {
			return err
		}
		open := func() (io.ReadCloser, error) { return io.NopCloser(bytes.NewReader(data)), nil }
		var bad assets.Refusal
		if err := assets.CheckFile(ctx, open, f, sc); errors.As(err, &bad) {
			return errorf(http.StatusBadRequest, fmt.Sprintf("%s: %s: %s", f.Field, f.Path, bad.Error()))
		} else if err != nil {
			return err
		}
		digest, err := blobs.UploadBytes(ctx, data)
		if err != nil {
			return err
		}
		stored[f.Path] = digest
		f.SetDigest(digest)
	}
	return nil
}
