package importer

import (
	"errors"
	"fmt"
	"io"
	"io/fs"
	"os"
	"path/filepath"
	"strings"

	"photonfarm/contract/assets"
)

// sourceFS serves the files a model names beside itself (glTF buffers and images, MTL
// files and their textures): only relative paths inside the model's folder, only regular
// files (a FIFO or a device would never end), and at most limit bytes each.
type sourceFS struct {
	dir   string
	limit int64
}

func (s sourceFS) path(name string) (string, error) {
	name = filepath.FromSlash(strings.ReplaceAll(name, `\`, "/"))
	if filepath.IsAbs(name) || !filepath.IsLocal(name) {
		return "", fmt.Errorf("%q is outside the model's folder %s", name, s.dir)
	}
	p := filepath.Join(s.dir, name)
	resolved, err := filepath.EvalSymlinks(p)
	if err != nil {
		return "", err
	}
	root, err := filepath.EvalSymlinks(s.dir)
	if err != nil {
		return "", err
	}
	if rel, err := filepath.Rel(root, resolved); err != nil || !filepath.IsLocal(rel) {
		return "", fmt.Errorf("%q leads through a symbolic link outside the model's folder %s", name, s.dir)
	}
	return resolved, nil
}

// Open implements fs.FS.
func (s sourceFS) Open(name string) (fs.File, error) {
	p, err := s.path(name)
	if err != nil {
		return nil, &fs.PathError{Op: "open", Path: name, Err: err}
	}
	st, err := os.Stat(p)
	if err != nil {
		return nil, err
	}
	if !st.Mode().IsRegular() {
		return nil, &fs.PathError{Op: "open", Path: name, Err: errors.New("not a regular file")}
	}
	if st.Size() > s.limit {
		return nil, &fs.PathError{Op: "open", Path: name, Err: fmt.Errorf("%d bytes, larger than the %d of one asset", st.Size(), s.limit)}
	}
	return os.Open(p)
}

// ReadFile reads a file the model names, as Open allows it.
func (s sourceFS) ReadFile(name string) ([]byte, error) {
	f, err := s.Open(name)
	if err != nil {
		return nil, err
	}
	defer f.Close()
	return io.ReadAll(io.LimitReader(f, s.limit+1))
}

// ReadModelFile reads a file a model in folder dir names, as the importer reads glTF
// buffers and images and MTL files and textures: only inside dir, only regular files,
// within the contract's asset size.
func ReadModelFile(dir, name string) ([]byte, error) {
	return sourceFS{dir: dir, limit: int64(assets.SceneLimits().MaxBytes)}.ReadFile(name)
}
