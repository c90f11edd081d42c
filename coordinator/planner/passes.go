package planner

import (
	"fmt"
	"slices"
	"strconv"
	"strings"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// Names of the passes a Plan lists, in order.
const (
	PassGlobalMap   = "global photon map"
	PassCausticMap  = "caustic photon map"
	PassPrecompute  = "irradiance precompute"
	PassFinalGather = "final gathering"
	PassDirect      = "direct lighting"
	PassMedia       = "participating media"
	PassVolumeMap   = "volume photon map"
	PassDispersion  = "dispersion"
	PassEdgeAA      = "edge antialiasing"
	PassRounds      = "progressive rounds"
	PassAdaptive    = "adaptive sampling"
)

// Passes returns every pass the renderer knows for s, each run or skipped with the reason.
// s must have passed scene.Validate.
func Passes(s *pb.Scene) *pb.Plan {
	var global, caustic, volume *scene.PhotonMap
	for _, m := range scene.PhotonMaps(s) {
		switch m.Kind {
		case pb.PhotonMapKind_PHOTON_MAP_KIND_GLOBAL:
			global = &m
		case pb.PhotonMapKind_PHOTON_MAP_KIND_CAUSTIC:
			caustic = &m
		case pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME:
			volume = &m
		}
	}
	shards := func(n uint64) uint64 { return scene.ShardsPerMap(s, n) }
	plan := &pb.Plan{MaxRounds: scene.Rounds(s)}
	add := func(name string, enabled bool, format string, args ...any) {
		plan.Passes = append(plan.Passes, &pb.PlannedPass{Name: name, Enabled: enabled, Reason: fmt.Sprintf(format, args...)})
	}

	inter := scene.InterreflectionOf(s)
	switch {
	case global != nil:
		add(PassGlobalMap, true, "%s photon paths per round in %d shards: %s", count(global.Photons), shards(global.Photons), inter.Why)
	case scene.GlobalPhotons(s) == 0:
		add(PassGlobalMap, false, "no global photons requested")
	default:
		add(PassGlobalMap, false, "%s", inter.Why)
	}
	if caustic != nil {
		add(PassCausticMap, true, "%s photon paths per round in %d shards: specular surfaces focus light onto diffuse ones",
			count(caustic.Photons), shards(caustic.Photons))
	} else if scene.SurfacesOf(s).Specular {
		add(PassCausticMap, false, "no caustic photons requested")
	} else {
		add(PassCausticMap, false, "no specular surface (mirror, glass, metal)")
	}

	switch {
	case global == nil:
		add(PassPrecompute, false, "no global photon map")
		add(PassFinalGather, false, "no global photon map")
	case !scene.FinalGather(s):
		add(PassPrecompute, false, "indirect.mode is PHOTON_MAP")
		add(PassFinalGather, false, "indirect.mode is PHOTON_MAP: the global map's radiance estimate is seen directly")
	default:
		add(PassPrecompute, true, "irradiance at the global map's irradiance sites (a site to every sixteenth of the photons an estimate gathers) in %d shards per round, merged into the snapshot", PrecomputeShards(s))
		add(PassFinalGather, true, "%d gather rays at a camera path's first diffuse hit, %d after a glossy bounce",
			scene.GatherRays(s), scene.SecondaryGatherRays(s))
	}

	add(PassDirect, true, "shadow rays to %s (%d samples per area light)", lightTargets(s), scene.LightSamples(s))
	dark := darkMedia(s)
	switch media := mediaOf(s); {
	case media == "":
		add(PassMedia, false, "no medium in the scene (medium and every shape's interior_medium unset): rays travel through vacuum, nothing is marched")
		add(PassVolumeMap, false, "no medium in the scene: no volume photons")
	case !scene.MediaScatter(s) && dark != "":
		add(PassMedia, true, "%s: %s", media, marching(s))
		add(PassVolumeMap, false, "no medium that light reaches scatters it, no volume photons: %s", dark)
	case !scene.MediaScatter(s):
		add(PassMedia, true, "%s: %s", media, marching(s))
		add(PassVolumeMap, false, "no medium scatters light (every sigma_s is 0, or every albedo or density is): the media only absorb, no volume photons")
	case volume == nil: // (volume_photons cannot be 0: it selects a default)
		add(PassMedia, true, "%s: %s; %s", media, marching(s), multipleScattering(s))
		add(PassVolumeMap, false, "every medium light reaches that scatters it has |g| >= %s: its multiple scattering is path traced, no volume photons%s", pathTracedAbsG(), noneFor(dark))
	default:
		add(PassMedia, true, "%s: %s; %s", media, marching(s), multipleScattering(s))
		add(PassVolumeMap, true, "%s volume photon paths per round in %d shards: photons stored where paths scatter in media of |g| < %s after their first bounce or scattering, gathered along camera and gather rays (k %d, radius %s)%s",
			count(volume.Photons), shards(volume.Photons), pathTracedAbsG(), volumeNeighbours(s), volumeRadius(s), noneFor(dark))
	}

	names := dispersiveMaterials(s)
	switch {
	case s.GetSampling().GetSpectral() == pb.SpectralSampling_SPECTRAL_SAMPLING_ALWAYS:
		past := "no dispersive material"
		if len(names) > 0 {
			past = strings.Join(names, ", ") + ": past it only the hero wavelength goes on"
		}
		add(PassDispersion, true, "sampling.spectral is ALWAYS: every photon and camera path is traced at %d wavelengths from its start (a hero and its companions), colours uplifted to spectra; %s",
			rules.Scene.GetSpectralWavelengthsPerPath(), past)
	case len(names) == 0:
		add(PassDispersion, false, "no dispersive material (no dielectric sets a dispersion): every path is traced in RGB")
	default:
		add(PassDispersion, true, "%s: light through it is traced at one wavelength from there on (photons and camera paths), in RGB elsewhere",
			strings.Join(names, ", "))
	}

	switch scene.AntialiasingMode(s) {
	case pb.AntialiasingMode_ANTIALIASING_MODE_NONE:
		add(PassEdgeAA, false, "antialiasing.mode is NONE: every pixel gets %d samples", scene.SamplesPerPixel(s))
	case pb.AntialiasingMode_ANTIALIASING_MODE_FULL:
		add(PassEdgeAA, true, "FULL: every pixel gets %d samples (the costly baseline edge antialiasing is measured against)", scene.EdgeSamples(s))
	default:
		add(PassEdgeAA, true, "%d samples on edge pixels (Sobel gradient of log-luminance above %s), more where a light borders the edge, %d elsewhere",
			scene.EdgeSamples(s), strconv.FormatFloat(scene.EdgeThreshold(s), 'g', -1, 64), scene.SamplesPerPixel(s))
	}

	add(PassRounds, scene.Rounds(s) > 1, "%s", roundsReason(s))
	adaptive, why := scene.Adaptive(s)
	add(PassAdaptive, adaptive, "%s", why)
	return plan
}

func roundsReason(s *pb.Scene) string {
	p := s.GetProgressive()
	n := scene.Rounds(s)
	if n == 1 {
		return "a single round (progressive.max_rounds is 1)"
	}
	parts := []string{fmt.Sprintf("up to %d rounds", n)}
	switch {
	case p.GetTargetError() > 0 && p.GetReference().GetDigest() != "":
		parts = append(parts, fmt.Sprintf("stop at reference RMSE <= %s", strconv.FormatFloat(p.GetTargetError(), 'g', -1, 64)))
	case p.GetTargetError() > 0:
		parts = append(parts, fmt.Sprintf("stop at estimated error <= %s", strconv.FormatFloat(p.GetTargetError(), 'g', -1, 64)))
	}
	if b := p.GetTimeBudgetSeconds(); b > 0 {
		parts = append(parts, fmt.Sprintf("no new round after %ss", strconv.FormatFloat(b, 'g', -1, 64)))
	}
	parts = append(parts, fmt.Sprintf("alpha %s", strconv.FormatFloat(scene.Alpha(s), 'g', -1, 64)))
	return strings.Join(parts, ", ")
}

// marching says what the renderer does in any medium, and in grids.
func marching(s *pb.Scene) string {
	samples := fmt.Sprintf("%d light samples and as many phase-function samples per segment, weighed by multiple importance sampling", scene.LightSamples(s))
	if !scene.HittableLights(s) {
		samples = fmt.Sprintf("%d light samples per segment: no phase-function sample can reach a point, spot or sun light without a disc", scene.LightSamples(s))
	}
	m := fmt.Sprintf("camera paths attenuated and single scattering from every light along them (%s), shadow rays attenuated", samples)
	if slices.ContainsFunc(scene.Media(s), func(m scene.Medium) bool { return m.Medium.GetGrid() != nil }) {
		m += "; through grids brick by brick (8^3 cells, empty ones skipped): optical depth integrated exactly, distances drawn by inverting it, free flights (photons, volumetric paths) delta-tracked against each brick's majorant"
	}
	return m
}

// multipleScattering says how light scattered more than once is found in s's scattering
// media: from the volume photon map, or (|g| at or above the contract's
// path_traced_media_min_abs_g) by volumetric path tracing, or each in its own media.
func multipleScattering(s *pb.Scene) string {
	const paths = "by volumetric path tracing (camera paths go on by the phase function, with light samples weighed by MIS)"
	switch mapped, traced := scene.VolumeMapNeeded(s), scene.MediaPathTraced(s); {
	case mapped && traced:
		return fmt.Sprintf("multiple scattering from the volume photon map, and %s in media of |g| >= %s", paths, pathTracedAbsG())
	case traced:
		return fmt.Sprintf("multiple scattering %s: |g| >= %s", paths, pathTracedAbsG())
	default:
		return "multiple scattering from the volume photon map"
	}
}

// pathTracedAbsG is the contract's path_traced_media_min_abs_g as people write it.
func pathTracedAbsG() string {
	return strconv.FormatFloat(rules.Scene.GetPathTracedMediaMinAbsG(), 'g', -1, 64)
}

// volumeNeighbours and volumeRadius are the volume estimate's k and search radius; their
// 0 selects a value per map (scene.proto's RadianceEstimate), the radius one the workers
// compute from the scene's bounds, which meshes in the blob store keep from the planner.
func volumeNeighbours(s *pb.Scene) uint32 {
	if k := s.GetPhotons().GetVolumeEstimate().GetNeighbours(); k > 0 {
		return k
	}
	return 50
}

func volumeRadius(s *pb.Scene) string {
	if r := s.GetPhotons().GetVolumeEstimate().GetMaxRadius(); r > 0 {
		return strconv.FormatFloat(r, 'g', -1, 64)
	}
	return "1/20 of the scene's diagonal"
}

// darkMedia names the scattering media no light reaches, each with why (scene.Media), ""
// for none: the volume map stores nothing in them (and no camera path sees them).
func darkMedia(s *pb.Scene) string {
	var parts []string
	for _, m := range scene.Media(s) {
		if m.Dark != "" && m.Scatters() {
			parts = append(parts, m.Label+": "+m.Dark)
		}
	}
	return strings.Join(parts, "; ")
}

// noneFor is what a pass that stores volume photons adds about dark, darkMedia's answer.
func noneFor(dark string) string {
	if dark == "" {
		return ""
	}
	return "; none for " + dark
}

// mediaOf names the media a scene holds ("fog filling the scene", "2 shapes' interior
// media", or both), "" for none.
func mediaOf(s *pb.Scene) string {
	var parts []string
	switch m := s.GetMedium(); {
	case m.GetGrid() != nil:
		parts = append(parts, "smoke from a grid filling the scene")
	case m != nil:
		parts = append(parts, "fog filling the scene")
	}
	interiors := 0
	for _, sh := range s.GetShapes() {
		if sh.GetInteriorMedium() != nil {
			interiors++
		}
	}
	switch interiors {
	case 0:
	case 1:
		parts = append(parts, "1 shape's interior medium")
	default:
		parts = append(parts, strconv.Itoa(interiors)+" shapes' interior media")
	}
	return strings.Join(parts, " and ")
}

// dispersiveMaterials names, in the order shapes first use them, the dispersive
// dielectrics the scene's shapes and mesh parts use, with their law: `material "prism"
// (BK7)`, `material "gem" (Abbe number 30)`.
func dispersiveMaterials(s *pb.Scene) []string {
	var names []string
	seen := map[string]bool{}
	for _, materials := range scene.ShapeMaterials(s) {
		for _, m := range materials {
			d := m.GetDielectric().GetDispersion()
			if d == nil || seen[m.GetName()] {
				continue
			}
			seen[m.GetName()] = true
			law := "Abbe number " + strconv.FormatFloat(d.GetAbbeNumber(), 'g', -1, 64)
			if _, ok := d.GetLaw().(*pb.Dispersion_Glass); ok {
				law = glassName(d.GetGlass())
			}
			names = append(names, fmt.Sprintf("material %q (%s)", m.GetName(), law))
		}
	}
	return names
}

// glassName is a Glass as its catalogue writes it: BK7, FUSED_SILICA, DIAMOND, SF11.
func glassName(g pb.Glass) string {
	if g == pb.Glass_GLASS_UNSPECIFIED {
		g = pb.Glass_GLASS_BK7
	}
	return strings.TrimPrefix(g.String(), "GLASS_")
}

func count(n uint64) string {
	s := strconv.FormatUint(n, 10)
	var b strings.Builder
	for i, c := range s {
		if i > 0 && (len(s)-i)%3 == 0 {
			b.WriteByte(',')
		}
		b.WriteRune(c)
	}
	return b.String()
}

// lightTargets says what shadow rays aim at: the lights, and the environment as one more
// light, which the workers also emit photons from, or not at all when it is black (the
// workers leave it out of both). An imported model without lights is lit by a sky alone.
func lightTargets(s *pb.Scene) string {
	lights := lightCount(s)
	switch {
	case s.GetEnvironment() == nil:
		return lights
	case !scene.EnvironmentLights(s):
		return lights + "; the environment is black: no shadow rays to it and no photons from it"
	case lights == "0 lights":
		return "the environment"
	default:
		return lights + " and the environment"
	}
}

func lightCount(s *pb.Scene) string {
	n := len(s.GetLights())
	for _, materials := range scene.ShapeMaterials(s) {
		for _, m := range materials {
			if scene.Emits(m) {
				n++ // an emissive shape, or an emissive part of an instanced mesh
			}
		}
	}
	if n == 1 {
		return "1 light"
	}
	return strconv.Itoa(n) + " lights"
}
