// Command gen writes the shared scene conformance vectors, tests/vectors/scenes/*.json
// (README.md there), from a valid base scene and one change each, and the asset files
// they name. Run from the repository's root after changing a rule or a case:
//
//	go run ./tests/vectors/scenes/gen
//
// and commit the result; gen_test.go fails while the committed files differ from what it
// makes, or while a rule of scene.proto has no vector.
package main

import "photonfarm/tests/vectors/vectorfiles"

// owned is the vectors the generator makes: one it no longer makes is removed.
const owned = vectorDir + "/*.json"

func main() { vectorfiles.Main("gen", Vectors, owned) }
