package client

import (
	"context"
	"errors"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"google.golang.org/grpc/metadata"

	"photonfarm/contract/rules"
)

func TestDialRefusesAPlaintextTokenToAnotherMachine(t *testing.T) {
	if _, err := Dial("farm.example:7070", WithToken("t")); !errors.Is(err, ErrPlaintextToken) {
		t.Errorf("plaintext token to farm.example: %v, want ErrPlaintextToken", err)
	}
	for _, ok := range [][]Option{
		{WithToken("t"), AllowPlaintextToken()},
		{WithToken("t"), WithTLS("")},
		{}, // no token, nothing to leak
	} {
		c, err := Dial("farm.example:7070", ok...)
		if err != nil {
			t.Errorf("Dial: %v", err)
			continue
		}
		c.Close()
	}
	c, err := Dial("127.0.0.1:7070", WithToken("t"))
	if err != nil {
		t.Fatalf("plaintext token to loopback: %v", err)
	}
	c.Close()
	if _, err := Dial("localhost:1", WithTLS(filepath.Join(t.TempDir(), "absent.pem"))); err == nil || !strings.Contains(err.Error(), "absent.pem") {
		t.Errorf("missing CA file: %v, want an error naming it", err)
	}
}

func TestIsLoopback(t *testing.T) {
	for addr, want := range map[string]bool{
		"localhost:7070": true, "127.0.0.1:1": true, "127.8.9.10:1": true, "[::1]:7070": true,
		"dns:///localhost:7070": true, "unix:/tmp/farm.sock": true, "a.localhost:1": true,
		"farm.example:7070": false, "10.0.0.1:7070": false, "[::]:7070": false, "0.0.0.0:1": false,
		"localhost.example.com:1": false,
	} {
		if got := IsLoopback(addr); got != want {
			t.Errorf("IsLoopback(%q) = %v, want %v", addr, got, want)
		}
	}
}

// assetTree is root/scenes/scene.json with root/scenes/meshes/tet.obj inside its asset
// root and root/outside.obj beside it.
func assetTree(t *testing.T, meshPath string) (root, scenePath string) {
	t.Helper()
	root = t.TempDir()
	scenes := filepath.Join(root, "scenes")
	if err := os.MkdirAll(filepath.Join(scenes, "meshes"), 0o755); err != nil {
		t.Fatal(err)
	}
	for _, f := range []string{filepath.Join(scenes, "meshes", "tet.obj"), filepath.Join(root, "outside.obj")} {
		if err := os.WriteFile(f, []byte(tetrahedron), 0o644); err != nil {
			t.Fatal(err)
		}
	}
	return root, writeScene(t, scenes, `{"shapes": [{"sphere": {"radius": 1}}, {"mesh": {"path": "`+meshPath+`"}}]}`)
}

func TestAssetRootRefusesPathsThatLeaveIt(t *testing.T) {
	root := t.TempDir()
	outside := filepath.Join(root, "outside.obj")
	for _, tc := range []struct {
		name, mesh string
		setup      func(scenes string)
		want       string
	}{
		{"dot-dot", "../outside.obj", nil, `"../outside.obj" is outside the asset root`},
		{"dot-dot inside a path", "meshes/../../outside.obj", nil, "is outside the asset root"},
		{"absolute path elsewhere", outside, nil, "is outside the asset root"},
		{"symlink to a file outside", "meshes/link.obj", func(scenes string) {
			os.Symlink(outside, filepath.Join(scenes, "meshes", "link.obj"))
		}, "leads through a symbolic link to"},
		{"symlinked folder outside", "shared/outside.obj", func(scenes string) {
			os.Symlink(root, filepath.Join(scenes, "shared"))
		}, "leads through a symbolic link to"},
	} {
		t.Run(tc.name, func(t *testing.T) {
			tree, scene := assetTree(t, tc.mesh)
			// The absolute case and the symlinks point at this test's own outside.obj.
			os.WriteFile(outside, []byte(tetrahedron), 0o644)
			if tc.setup != nil {
				tc.setup(filepath.Join(tree, "scenes"))
			}
			_, err := ReadSceneFile(context.Background(), scene)
			if err == nil {
				t.Fatal("a mesh outside the asset root was accepted")
			}
			msg := err.Error()
			if !strings.HasPrefix(msg, "shapes[1].mesh.path: ") || !strings.Contains(msg, tc.want) ||
				!strings.Contains(msg, filepath.Join(tree, "scenes")) || !IsInvalidInput(err) {
				t.Errorf("error %q: want shapes[1].mesh.path, %q and the root %s, invalid input", msg, tc.want, filepath.Join(tree, "scenes"))
			}
		})
	}
}

func TestAssetRootAcceptsFilesInside(t *testing.T) {
	tree, scene := assetTree(t, "meshes/tet.obj")
	// A symbolic link that stays inside is fine too.
	if err := os.Symlink(filepath.Join(tree, "scenes", "meshes", "tet.obj"), filepath.Join(tree, "scenes", "alias.obj")); err != nil {
		t.Fatal(err)
	}
	sf, err := ReadSceneFile(context.Background(), scene)
	if err != nil {
		t.Fatal(err)
	}
	if len(sf.Meshes) != 1 || sf.Meshes[0].Digest != rules.DigestOf([]byte(tetrahedron)) {
		t.Errorf("meshes = %+v", sf.Meshes)
	}
	_, aliased := assetTree(t, "alias.obj")
	os.Symlink(filepath.Join(filepath.Dir(aliased), "meshes", "tet.obj"), filepath.Join(filepath.Dir(aliased), "alias.obj"))
	if _, err := ReadSceneFile(context.Background(), aliased); err != nil {
		t.Errorf("symlink inside the root: %v", err)
	}
	// A wider root admits ../outside.obj.
	_, up := assetTree(t, "../outside.obj")
	if _, err := ReadSceneFile(context.Background(), up, WithAssetRoot(filepath.Dir(filepath.Dir(up)))); err != nil {
		t.Errorf("with the parent folder as asset root: %v", err)
	}
	// A missing file inside the root is still reported as missing.
	_, missing := assetTree(t, "meshes/absent.obj")
	if _, err := ReadSceneFile(context.Background(), missing); err == nil || !strings.Contains(err.Error(), "open meshes/absent.obj: no such file or directory") {
		t.Errorf("missing mesh: %v", err)
	}
}

func TestAssetRootAppliesToTheReferenceImage(t *testing.T) {
	root := t.TempDir()
	scenes := filepath.Join(root, "scenes")
	os.MkdirAll(scenes, 0o755)
	os.WriteFile(filepath.Join(root, "ref.exr"), []byte("not really"), 0o644)
	scene := writeScene(t, scenes, `{"shapes": [{"sphere": {"radius": 1}}], "progressive": {"reference": {"path": "../ref.exr"}}}`)
	_, err := ReadSceneFile(context.Background(), scene)
	if err == nil || !strings.Contains(err.Error(), "progressive.reference.path") || !strings.Contains(err.Error(), "outside the asset root") {
		t.Errorf("reference outside the root: %v", err)
	}
}

func TestContextWithTokenSendsTheBearerHeader(t *testing.T) {
	md, _ := metadata.FromOutgoingContext(ContextWithToken(context.Background(), "tok"))
	if got := md.Get("authorization"); len(got) != 1 || got[0] != "Bearer tok" {
		t.Errorf("authorization metadata = %q, want [\"Bearer tok\"]", got)
	}
	if _, ok := metadata.FromOutgoingContext(ContextWithToken(context.Background(), "")); ok {
		t.Error("an empty token sent metadata")
	}
}
