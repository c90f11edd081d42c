package main

import (
	"context"
	"fmt"
	"io"
	"os"
	"path/filepath"
	"strings"

	"photonfarm/client"
	"photonfarm/client/importer"
)

var importVerb = &verb{
	name:    "import",
	args:    "MODEL -o SCENE.json [--width N] [--height N] [--environment IMAGE]",
	summary: "turn a glTF (.gltf, .glb) or OBJ model into a scene file beside its meshes and images",
	run:     runImport,
}

func runImport(ctx context.Context, e *env, args []string) error {
	fs := newFlags("import", e)
	out := fs.String("o", "", "the scene `file` to write (its meshes and images go in its folder)")
	opt := importFlags(fs)
	pos, err := parse(fs, args, 1, 1)
	if err != nil {
		return err
	}
	if *out == "" {
		return usageErrorf("import: -o SCENE.json is required")
	}
	r, err := importer.Import(ctx, pos[0], filepath.Dir(*out), opt())
	if err != nil {
		return err
	}
	if err := importer.WriteScene(*out, r.Scene); err != nil {
		return err
	}
	reportImport(e.stdout, r)
	fmt.Fprintf(e.stdout, "wrote %s\n", *out)
	return nil
}

// importFlags are the flags of verbs that may import a model: the film size.
func importFlags(fs *flagSet) func() importer.Options {
	width := fs.Uint("width", 640, "film width in `pixels` when importing a model")
	height := fs.Uint("height", 0, "film height in `pixels` when importing a model (0: the camera's aspect ratio)")
	env := fs.String("environment", "", "an equirectangular `image` (OpenEXR or Radiance HDR) to light an imported model with")
	return func() importer.Options {
		return importer.Options{Width: uint32(*width), Height: uint32(*height), Environment: *env}
	}
}

// reportImport says what an import made, chose and skipped.
func reportImport(w io.Writer, r *importer.Result) {
	for _, s := range r.Chose {
		fmt.Fprintf(w, "chose: %s\n", s)
	}
	for _, s := range r.Skipped {
		fmt.Fprintf(w, "skipped: %s\n", s)
	}
	fmt.Fprintf(w, "imported %d meshes, %d materials, %d textures, %d instances, %d lights\n",
		len(r.Scene.GetMeshes()), len(r.Scene.GetMaterials()), len(r.Scene.GetTextures()), len(r.Scene.GetShapes()), len(r.Scene.GetLights()))
}

// isModel reports whether path names a model to import rather than a scene file.
func isModel(path string) bool {
	switch strings.ToLower(filepath.Ext(path)) {
	case ".gltf", ".glb", ".obj":
		return true
	}
	return false
}

// readScene reads the scene a verb is given: a scene file, or a model imported into a
// temporary folder first (whose files are then the asset root; what the import did is
// reported on report). cleanup removes that folder.
func readScene(ctx context.Context, report io.Writer, path, assetRoot string, opt importer.Options) (sf *client.SceneFile, cleanup func(), err error) {
	if !isModel(path) {
		sf, err := client.ReadSceneFile(ctx, path, client.WithAssetRoot(assetRoot))
		if err == nil && sf.Scene.GetName() == "" {
			// The job's display name names its outputs, for farm render and farm fetch
			// alike: a nameless scene is named after its file.
			sf.Scene.Name = client.SceneStem(path)
		}
		return sf, func() {}, err
	}
	dir, err := os.MkdirTemp("", "farm-import-")
	if err != nil {
		return nil, nil, err
	}
	cleanup = func() { os.RemoveAll(dir) }
	r, err := importer.Import(ctx, path, dir, opt)
	if err != nil {
		cleanup()
		return nil, nil, err
	}
	reportImport(report, r)
	scenePath := filepath.Join(dir, client.SceneStem(path)+".json")
	if err := importer.WriteScene(scenePath, r.Scene); err != nil {
		cleanup()
		return nil, nil, err
	}
	sf, err = client.ReadSceneFile(ctx, scenePath, client.WithAssetRoot(dir))
	if err != nil {
		cleanup()
		return nil, nil, err
	}
	return sf, cleanup, nil
}
