package scene_test

import (
	"strings"
	"testing"

	"photonfarm/contract/scene"
)

func TestParseJSON(t *testing.T) {
	valid := `{
  "name": "t",
  "camera": {"position": {"x": 0, "y": 1, "z": 5}, "lookAt": {"y": 1}, "up": {"y": 1}, "vertical_fov_degrees": 40},
  "film": {"width": 8, "height": 8},
  "materials": [{"name": "l", "emissive": {"radiance": {"r": 1, "g": 1, "b": 1}}}],
  "shapes": [{"material": "l", "sphere": {"center": {}, "radius": 1}}]
}`
	tests := []struct {
		name    string
		in      string
		wantErr []string // substrings; none means success
	}{
		{"valid, both field spellings", valid, nil},
		{"unknown field", `{"shapes": [{"sphere": {"radus": 1}}]}`,
			[]string{`scene: line 1:25: shapes[0].sphere.radus: unknown field "radus" (did you mean "radius"?)`}},
		{"misspelled field with its line", "{\n  \"film\": {\"width\": 8,\n    \"widht\": 8}}",
			[]string{`scene: line 3:5: film.widht: unknown field "widht" (did you mean "width"?)`}},
		{"misspelled field in a later element", `{"shapes": [{"sphere": {}}, {}, {"sphere": {"centre": {}}}]}`,
			[]string{`shapes[2].sphere.centre: unknown field "centre" (did you mean "center"?)`}},
		{"misspelled proto name", `{"film": {"tile_sise": 8}}`,
			[]string{`film.tile_sise: unknown field "tile_sise" (did you mean "tileSize"?)`}},
		{"unknown field far from any", `{"film": {"depth": 8}}`,
			[]string{`film.depth: unknown field "depth"`}},
		{"misspelled enum value", `{"output": {"toneMap": "TONE_MAP_FILMC"}}`,
			[]string{`output.tone_map: unknown value "TONE_MAP_FILMC" (did you mean "TONE_MAP_FILMIC"?)`}},
		{"type error before a misspelling is protojson's", `{"film": {"width": "wide", "widht": 8}}`,
			[]string{"scene: ", `"wide"`}},
		{"bad JSON", "{\n  \"name\": \"x\",\n  \"film\": {\"width\": 8,,}\n}", []string{"scene: ", "line 3:"}},
		{"wrong type", `{"film": {"width": "wide"}}`, []string{"scene: ", "width"}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			s, err := scene.ParseJSON([]byte(tt.in))
			if tt.wantErr == nil {
				if err != nil {
					t.Fatalf("ParseJSON: %v", err)
				}
				if err := scene.Validate(s); err != nil {
					t.Fatalf("Validate: %v", err)
				}
				return
			}
			if err == nil {
				t.Fatal("ParseJSON succeeded, want an error")
			}
			for _, w := range tt.wantErr {
				if !strings.Contains(err.Error(), w) {
					t.Errorf("error %q does not contain %q", err, w)
				}
			}
			if tt.name == "unknown field far from any" && strings.Contains(err.Error(), "did you mean") {
				t.Errorf("error %q suggests a name too far from the one written", err)
			}
			if strings.Contains(err.Error(), "proto:") {
				t.Errorf("error %q leaks protojson's prefix", err)
			}
		})
	}
}
