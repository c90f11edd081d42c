package client

import (
	"context"
	"errors"
	"os"
	"path/filepath"
	"strings"
	"syscall"
	"testing"
	"time"
)

func TestReadSceneFileRefusesABrokenMeshBeforeUploading(t *testing.T) {
	dir := t.TempDir()
	os.MkdirAll(filepath.Join(dir, "meshes"), 0o755)
	os.WriteFile(filepath.Join(dir, "meshes", "broken.obj"), []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 7\n"), 0o644)
	scene := writeScene(t, dir, `{"shapes": [{"sphere": {"radius": 1}}, {"mesh": {"path": "meshes/broken.obj"}}]}`)
	_, err := ReadSceneFile(context.Background(), scene)
	want := "shapes[1].mesh: meshes/broken.obj: line 5: face refers to vertex 7 but the file has 3 vertices"
	var e *Error
	if err == nil || err.Error() != want || !errors.As(err, &e) || e.Field != "shapes[1].mesh" || !IsInvalidInput(err) {
		t.Errorf("got %v, want the invalid input %q", err, want)
	}
}

func TestReadSceneFileRefusesWhatIsNotARegularFileOfAllowedSize(t *testing.T) {
	dir := t.TempDir()
	fifo := filepath.Join(dir, "pipe.obj")
	if err := syscall.Mkfifo(fifo, 0o644); err != nil {
		t.Fatal(err)
	}
	os.Mkdir(filepath.Join(dir, "folder.obj"), 0o755)
	for _, tc := range []struct{ name, path, want string }{
		{"a device", "/dev/zero", "read /dev/zero: not a regular file"},
		{"a pipe", "pipe.obj", "read pipe.obj: not a regular file"},
		{"a folder", "folder.obj", "read folder.obj: not a regular file"},
	} {
		scene := writeScene(t, dir, `{"shapes": [{"mesh": {"path": "`+tc.path+`"}}]}`)
		done := make(chan error, 1)
		go func() {
			_, err := ReadSceneFile(context.Background(), scene, WithAssetRoot("/"))
			done <- err
		}()
		select {
		case err := <-done:
			if err == nil || !strings.Contains(err.Error(), "shapes[0].mesh.path: "+tc.want) {
				t.Errorf("%s: got %v, want %q", tc.name, err, tc.want)
			}
		case <-time.After(5 * time.Second):
			t.Fatalf("%s: still reading after 5 s", tc.name)
		}
	}
}

func TestReadSceneFileStopsWhenTheContextEnds(t *testing.T) {
	dir := t.TempDir()
	os.WriteFile(filepath.Join(dir, "tet.obj"), []byte(tetrahedron), 0o644)
	scene := writeScene(t, dir, `{"shapes": [{"mesh": {"path": "tet.obj"}}]}`)
	ctx, cancel := context.WithCancel(context.Background())
	cancel()
	if _, err := ReadSceneFile(ctx, scene); !errors.Is(err, context.Canceled) {
		t.Errorf("got %v, want context.Canceled", err)
	}
}
