package main

import (
	"fmt"
	"math/bits"
	"strings"

	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

// example is a refusal as the coordinator words it.
func example() string {
	s := scenetest.Valid(64, 48)
	s.Film.Width = 20000
	return fmt.Sprintf("```\n%v\n```", scene.Validate(s))
}

// sceneFields is a table of every field of a scene that has a rule (or is an enum, whose
// value must be declared) and every required oneof, by the path errors name them by.
func sceneFields() string {
	var b strings.Builder
	b.WriteString("| Field | Rule | Checked by hand |\n|---|---|---|\n")
	var walk func(md protoreflect.MessageDescriptor, path string)
	walk = func(md protoreflect.MessageDescriptor, path string) {
		for i := 0; i < md.Fields().Len(); i++ {
			fd := md.Fields().Get(i)
			p := join(path, string(fd.Name()))
			if rule := describe(fd); rule != "" || rules.Of(fd).GetNote() != "" {
				fmt.Fprintf(&b, "| `%s` | %s | %s |\n", p, rule, rules.Of(fd).GetNote())
			}
			if fd.Kind() == protoreflect.MessageKind {
				if fd.IsList() {
					p += "[i]"
				}
				walk(fd.Message(), p)
			}
		}
		for i := 0; i < md.Oneofs().Len(); i++ {
			if od := md.Oneofs().Get(i); rules.OneRequired(od) {
				var names []string
				for j := 0; j < od.Fields().Len(); j++ {
					names = append(names, "`"+string(od.Fields().Get(j).Name())+"`")
				}
				fmt.Fprintf(&b, "| `%s` | exactly one of %s | |\n", path, strings.Join(names, ", "))
			}
		}
	}
	walk((*pb.Scene)(nil).ProtoReflect().Descriptor(), "")
	return b.String()
}

// describe says in words what field fd's rule (and, for an enum, its type) allows.
func describe(fd protoreflect.FieldDescriptor) string {
	r := rules.Of(fd)
	if r == nil {
		r = &pb.FieldRule{}
	}
	var parts []string
	if r.GetRequired() {
		parts = append(parts, "required")
	}
	if d := strings.TrimPrefix(rules.Describe(r), "must be "); d != "" {
		if fd.Kind() == protoreflect.MessageKind {
			d = "each component " + d
		}
		parts = append(parts, d)
	}
	if fd.Kind() == protoreflect.EnumKind {
		e := "a declared `" + string(fd.Enum().Name()) + "` value"
		if r.DefaultValue != nil {
			e += "; unset selects `" + string(fd.Enum().Values().ByNumber(protoreflect.EnumNumber(r.GetDefaultValue())).Name()) + "`"
		}
		parts = append(parts, e)
	}
	if r.MinItems != nil {
		parts = append(parts, fmt.Sprintf("at least %d entries", r.GetMinItems()))
	}
	if r.MaxItems != nil {
		parts = append(parts, fmt.Sprintf("at most %d entries", r.GetMaxItems()))
	}
	if r.MaxBytes != nil {
		parts = append(parts, fmt.Sprintf("at most %d bytes", r.GetMaxBytes()))
	}
	if r.GetDigest() {
		parts = append(parts, "`sha256:` and 64 lowercase hex digits")
	}
	return strings.Join(parts, "; ")
}

// sceneLimits is a table of the scene_limits option of Scene.
func sceneLimits() string {
	return optionTable(rules.Scene.ProtoReflect(), map[string]string{
		"max_magnitude":                 "largest magnitude of any double in a scene (coordinates, radii, colour components, angles), which must also be finite",
		"max_tiles_per_round":           "render tiles in one round: `ceil(film.width / t) * ceil(film.height / t)`, t the tile size (refused as `film.tile_size`)",
		"max_shards_per_map":            "emission shards of one photon map in one round: `ceil(photons / photons_per_shard)`, for each of the global, caustic and volume photon counts, whether or not the scene gets that map (refused as `photons.photons_per_shard`)",
		"max_asset_bytes":               "largest mesh file (and any other asset) a scene names: a worker holds a mesh file's bytes while it parses them",
		"max_mesh_vertices":             "most vertices in one mesh file",
		"max_mesh_triangles":            "most triangles in one mesh file, after splitting polygons: the largest mesh takes a worker about 2.6 GB to parse and put in Embree's BVH (measured: about 260 bytes a triangle, see Worker memory below)",
		"max_mesh_line_bytes":           "longest line of a mesh file, its line break included",
		"max_film_pixels":               "pixels of the film, `film.width * film.height` (refused as `film.height`): the composite holds the film's tiles and images (measured: about 340 bytes a pixel on the worker), and the image and accumulation EXRs (84 and 96 bytes a pixel uncompressed: 705 and 805 MB at the limit) must stay under `max_blob_bytes`; 8,388,608 holds 3840x2160",
		"max_snapshot_photons":          fmt.Sprintf("photons stored in one round's photon snapshot, every map together (a path stores a photon at each diffuse bounce, so `photons.*_photons` alone do not bound it): the coordinator's builder fails a snapshot that stores more as bad input naming the setting to lower. The largest snapshot, every photon global with irradiance (24 bytes each), is then %s, under `max_blob_bytes`; building it takes the coordinator 24 bytes a photon of the largest map and a scratch file of the snapshot's size in `--data-dir` (Memory, measured, below), and each worker maps it whole", gibibytes(largestSnapshot())),
		"max_shard_photons":             fmt.Sprintf("photons stored by one emission shard (whatever the scene stores a path): the worker stops tracing a shard that stores more and fails it as bad input saying to lower `photons.photons_per_shard`; the largest shard, which the worker holds while it traces and uploads it, is then %s (28 bytes a photon)", gibibytes(40+28*rules.Scene.GetMaxShardPhotons())),
		"max_texture_pixels":            "most pixels (width times height) of one texture, read from its header without decoding it",
		"principled_specular_roughness": "a principled material whose roughness factor is below this counts as specular: its lobe is only sampled, never lit by light samples or photons, and the scene gets a caustic map",
		"max_grid_cells":                "most cells (`nx * ny * nz`) of one farm grid file (docs/grid-format.md): a worker holds 4 bytes a cell, plus a majorant for every 8 x 8 x 8 brick, for the job's life (256 MiB at the limit)",
		"max_grid_axis_cells":           "most cells along each axis of a farm grid file, checked before the counts are multiplied",
		"path_traced_media_min_abs_g":   "a medium whose Henyey-Greenstein g is at least this in absolute value scatters light more than once by volumetric path tracing (phase-function sampling with light samples weighed by MIS) rather than from the volume photon map, whose k photons cannot weigh so narrow a lobe; the planner leaves the volume map out when no scattering medium that light reaches is below it; homogeneous and grid media alike (docs/media.md)",
		"spectral_wavelengths_per_path": "wavelengths a photon or camera path carries with `sampling.spectral` ALWAYS (a hero and its companions, docs/spectral.md); the workers check theirs against it",
	})
}

// rpcLimits is a table of the rpc_limits option of blob.proto.
func rpcLimits() string {
	return optionTable(rules.RPC.ProtoReflect(), map[string]string{
		"max_message_bytes":        "largest gRPC message either way (room for a chunk and for scenes with inline meshes)",
		"max_upload_chunk_bytes":   "largest `UploadBlob` chunk",
		"max_download_chunk_bytes": "largest `DownloadBlob` chunk",
		"max_blob_bytes":           "largest blob (`RESOURCE_EXHAUSTED` past it)",
		"max_error_bytes":          "longest `FailTaskRequest.error` kept; longer ones are truncated",
		"max_task_log_bytes":       "largest task log (`task.log`, a completed task's output or `FailTaskRequest.log`): the worker keeps the task's first and last lines within it and says how many lines it left out between them; the coordinator refuses a bigger one",
	})
}

// optionTable lists every field of an options message with its value and meaning; it
// panics for a field with no meaning, so that a new limit cannot go undocumented.
func optionTable(m protoreflect.Message, meanings map[string]string) string {
	var b strings.Builder
	b.WriteString("| Limit | Value | What |\n|---|---|---|\n")
	fields := m.Descriptor().Fields()
	for i := 0; i < fields.Len(); i++ {
		fd := fields.Get(i)
		meaning, ok := meanings[string(fd.Name())]
		if !ok {
			panic("docs/gen: say what " + string(fd.FullName()) + " means")
		}
		var value string
		switch v := m.Get(fd); fd.Kind() {
		case protoreflect.DoubleKind:
			value = rules.Number(v.Float())
		default:
			value = amount(v.Uint(), strings.HasSuffix(string(fd.Name()), "_bytes"))
		}
		fmt.Fprintf(&b, "| `%s` | %s | %s |\n", fd.Name(), value, meaning)
	}
	return b.String()
}

// largestSnapshot is the size of the largest snapshot: max_snapshot_photons global photons
// with irradiance (docs/photon-snapshot.md: a header and one directory entry of 64 bytes,
// 20 bytes a photon, 4 of irradiance).
func largestSnapshot() uint64 { return 64 + 64 + 24*rules.Scene.GetMaxSnapshotPhotons() }

// gibibytes writes a size in bytes and GiB.
func gibibytes(n uint64) string {
	return fmt.Sprintf("%s bytes (%.2f GiB)", commas(n), float64(n)/(1<<30))
}

// commas writes n with thousands separators.
func commas(n uint64) string {
	s := fmt.Sprint(n)
	for i := len(s) - 3; i > 0; i -= 3 {
		s = s[:i] + "," + s[i:]
	}
	return s
}

// amount writes n, in MiB or GiB when it is bytes and a whole number of them.
func amount(n uint64, isBytes bool) string {
	if !isBytes {
		return fmt.Sprint(n)
	}
	for _, u := range []struct {
		name  string
		shift int
	}{{"GiB", 30}, {"MiB", 20}} {
		if n >= 1<<u.shift && bits.TrailingZeros64(n) >= u.shift {
			return fmt.Sprintf("%d %s", n>>u.shift, u.name)
		}
	}
	return fmt.Sprintf("%d bytes", n)
}

// planning says what the limits make of a job's size.
func planning() string {
	tiles, shards := rules.Scene.GetMaxTilesPerRound(), rules.Scene.GetMaxShardsPerMap()
	rounds := uint64(rules.Max((*pb.Progressive)(nil), "max_rounds"))
	side := uint64(rules.Max((*pb.Film)(nil), "width"))
	return fmt.Sprintf("Planning a round makes a task per render tile and per emission shard, so these limits bound it: "+
		"a round has at most %d render tiles and a composite, and per photon map (global, caustic, volume) at most %d emission shards, "+
		"then a build, %d irradiance precompute tasks (one per global shard) and a merge: %d tasks at most "+
		"(`TestPlanLargestRoundStaysWithinLimits` plans that round). A job has at most %d rounds; each is planned when the one before has ended. "+
		"A job of a million tiles is refused at submit (and by `farm validate` and `farm plan`) before anything is planned or stored, naming the limit: "+
		"a %dx%d film in 16-pixel tiles makes %d tiles, more than `max_tiles_per_round` (refused as `film.tile_size`), and in any tiles it has %d pixels, more than `max_film_pixels` "+
		"(`TestTooManyTasksAreRefusedAtSubmitAndPlan`). Planning such a round lazily, in pages of tasks, is not done.",
		tiles, shards, shards, largestRound(), rounds, side, side, (side/16)*(side/16), side*side)
}

// largestRound is how many tasks the largest round the limits allow has: its tiles and a
// composite, the shards of all three maps, a build, a precompute task per global shard and
// a merge.
func largestRound() int {
	tiles, shards := int(rules.Scene.GetMaxTilesPerRound()), int(rules.Scene.GetMaxShardsPerMap())
	return tiles + 1 + 3*shards + 1 + shards + 1
}

func join(path, name string) string {
	if path == "" {
		return name
	}
	return path + "." + name
}
