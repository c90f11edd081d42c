package main

import (
	"context"
	"fmt"
	"io"

	"photonfarm/client"
	"photonfarm/client/importer"
	"photonfarm/contract/scene"
)

var validateVerb = &verb{
	name:    "validate",
	args:    "SCENE|MODEL... [--asset-root DIR] [--width N] [--height N]",
	summary: "check scene files as the coordinator would, with no coordinator",
	run:     runValidate,
}

func runValidate(ctx context.Context, e *env, args []string) error {
	fs := newFlags("validate", e)
	assetRoot := assetRootFlag(fs)
	imports := importFlags(fs)
	pos, err := parse(fs, args, 1, -1)
	if err != nil {
		return err
	}
	for _, path := range pos {
		_, cleanup, err := checkScene(ctx, e.stderr, path, *assetRoot, imports())
		if err != nil {
			return err
		}
		cleanup()
		fmt.Fprintf(e.stdout, "%s: ok\n", path)
	}
	return nil
}

// checkScene reads the scene (or model) at path, checks the files it names, and
// validates it by the contract, here and now: the checks SubmitJob makes, but for the
// blob store's. Errors name the file first. report gets what an import did.
func checkScene(ctx context.Context, report io.Writer, path, assetRoot string, opt importer.Options) (*client.SceneFile, func(), error) {
	sf, cleanup, err := readScene(ctx, report, path, assetRoot, opt)
	if err != nil {
		return nil, nil, err
	}
	if err := scene.Validate(sf.Scene); err != nil {
		cleanup()
		return nil, nil, usageErrorf("%s: %v", path, err)
	}
	return sf, cleanup, nil
}
