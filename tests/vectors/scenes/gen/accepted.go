package main

import (
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

// accepted lists the scenes every side must accept: each inclusive bound hit exactly, and
// 0 wherever a default applies (0 is not written in JSON: such a case is base without the
// field). The scene files of scenes/ are accepted too (sceneFiles).
var accepted = slices.Concat(acceptedFilters, acceptedMedia, acceptedDispersion, []vectorCase{
	accept("accept-base", "TriangleMesh.positions:min_items=", unchanged),
	accept("accept-mesh-named-by-path-and-digest", "", func(s *pb.Scene) { withMesh(s) }),
	accept("accept-coordinates-at-max-magnitude", "Scene:max_magnitude=", func(s *pb.Scene) {
		sphere(s).Center, sphere(s).Radius = v(1e12, -1e12, 0), 1e12
	}),

	// Names and paths at their longest.
	accept("accept-scene-name-of-256-bytes", "Scene.name:max_bytes=", func(s *pb.Scene) { s.Name = long(256) }),
	accept("accept-material-name-of-256-bytes", "Material.name:max_bytes=", func(s *pb.Scene) {
		s.Materials[3].Name, s.Shapes[4].Material = long(256), long(256)
	}),
	accept("accept-shape-name-of-256-bytes", "Shape.name:max_bytes=", func(s *pb.Scene) { s.Shapes[2].Name = long(256) }),
	accept("accept-light-name-of-256-bytes", "Light.name:max_bytes=", func(s *pb.Scene) { s.Lights[1].Name = long(256) }),
	accept("accept-mesh-path-of-4096-bytes", "MeshFile.path:max_bytes=", func(s *pb.Scene) { withMesh(s).Path = long(4096) }),
	accept("accept-reference-path-of-4096-bytes", "ReferenceImage.path:max_bytes=", func(s *pb.Scene) {
		s.Progressive.Reference = &pb.ReferenceImage{Path: long(4096), Digest: absentDigest}
	}),

	// Lists at their longest.
	accept("accept-100000-shapes", "Scene.shapes:max_items=", unchanged, grow("shapes", 100000)),
	accept("accept-4096-lights", "Scene.lights:max_items=", unchanged, grow("lights", 4096)),
	accept("accept-triangles-with-1000000-positions-and-3000000-indices", "TriangleMesh.positions:max_items= TriangleMesh.indices:max_items=", unchanged,
		grow("shapes[3].triangles.positions", 1000000), grow("shapes[3].triangles.indices", 3000000)),

	// Film and sampling.
	accept("accept-film-of-1-pixel", "Film.width:gte= Film.height:gte=", func(s *pb.Scene) { s.Film.Width, s.Film.Height = 1, 1 }),
	accept("accept-film-16384-wide-at-the-pixel-limit", "Film.width:lte= Scene:max_film_pixels=", func(s *pb.Scene) {
		s.Film.Width, s.Film.Height, s.Film.TileSize = 16384, 512, 64
	}),
	accept("accept-film-16384-high-at-the-pixel-limit", "Film.height:lte=", func(s *pb.Scene) {
		s.Film.Width, s.Film.Height, s.Film.TileSize = 512, 16384, 64
	}),
	accept("accept-65536-tiles-per-round-of-8-pixels", "Scene:max_tiles_per_round=", func(s *pb.Scene) {
		s.Film.Width, s.Film.Height, s.Film.TileSize = 2048, 2048, 8
	}),
	accept("accept-tile-size-8", "Film.tile_size:gte=", func(s *pb.Scene) { s.Film.TileSize = 8 }),
	accept("accept-tile-size-256", "Film.tile_size:lte=", func(s *pb.Scene) { s.Film.TileSize = 256 }),
	accept("accept-tile-size-0", "Film.tile_size:default", func(s *pb.Scene) { s.Film.TileSize = 0 }),
	accept("accept-samples-per-pixel-65536", "Sampling.samples_per_pixel:lte=", func(s *pb.Scene) { s.Sampling.SamplesPerPixel = 65536 }),
	accept("accept-samples-per-pixel-0", "Sampling.samples_per_pixel:default", func(s *pb.Scene) { s.Sampling.SamplesPerPixel = 0 }),
	accept("accept-light-samples-1024", "Sampling.light_samples:lte=", func(s *pb.Scene) { s.Sampling.LightSamples = 1024 }),
	accept("accept-light-samples-0", "Sampling.light_samples:default", func(s *pb.Scene) { s.Sampling.LightSamples = 0 }),

	// Materials at their bounds.
	accept("accept-lambert-reflectance-0-and-1", "Lambert.reflectance:gte= Lambert.reflectance:lte=", func(s *pb.Scene) { lambert(s).Reflectance = rgb(0, 1, 0) }),
	accept("accept-emissive-radiance-0-in-one-channel", "Emissive.radiance:gte=", func(s *pb.Scene) { emissive(s).Radiance.B = 0 }),
	accept("accept-emissive-reflectance-0-and-1", "Emissive.reflectance:gte= Emissive.reflectance:lte=", func(s *pb.Scene) { emissive(s).Reflectance = rgb(0, 1, 0.78) }),
	accept("accept-glossy-diffuse-0-and-1", "Glossy.diffuse:gte= Glossy.diffuse:lte=", func(s *pb.Scene) {
		glossy(s).Diffuse, glossy(s).Specular = rgb(1, 0, 0.5), rgb(0, 0.5, 0.5)
	}),
	accept("accept-glossy-specular-0-and-1", "Glossy.specular:gte= Glossy.specular:lte=", func(s *pb.Scene) {
		glossy(s).Diffuse, glossy(s).Specular = rgb(0, 0.5, 0.5), rgb(1, 0, 0.5)
	}),
	accept("accept-glossy-diffuse-plus-specular-exactly-1", "", func(s *pb.Scene) { glossy(s).Diffuse = rgb(0.5, 0.25, 0.5) }),
	accept("accept-glossy-exponent-1", "Glossy.exponent:gte=", func(s *pb.Scene) { glossy(s).Exponent = 1 }),
	accept("accept-glossy-exponent-100000", "Glossy.exponent:lte=", func(s *pb.Scene) { glossy(s).Exponent = 100000 }),
	accept("accept-mirror-reflectance-0-and-1", "Mirror.reflectance:gte= Mirror.reflectance:lte=", func(s *pb.Scene) { mirror(s).Reflectance = rgb(1, 0, 1) }),
	accept("accept-ior-1", "Dielectric.ior:gte=", func(s *pb.Scene) { dielectric(s).Ior = 1 }),
	accept("accept-ior-10", "Dielectric.ior:lte=", func(s *pb.Scene) { dielectric(s).Ior = 10 }),
	accept("accept-transmittance-0-and-1", "Dielectric.transmittance:gte= Dielectric.transmittance:lte=", func(s *pb.Scene) {
		dielectric(s).Transmittance = rgb(0, 1, 0)
	}),
	accept("accept-dielectric-without-transmittance", "", func(s *pb.Scene) { dielectric(s).Transmittance = nil }),
	accept("accept-conductor-eta-100", "Conductor.eta:lte=", func(s *pb.Scene) { conductor(s).Eta.B = 100 }),
	accept("accept-conductor-k-0-and-100", "Conductor.k:gte= Conductor.k:lte=", func(s *pb.Scene) { conductor(s).K = rgb(0, 100, 1) }),

	// Lights at their bounds.
	accept("accept-point-intensity-0", "PointLight.intensity:gte=", func(s *pb.Scene) { point(s).Intensity = rgb(0, 0, 0) }),
	accept("accept-sun-irradiance-0", "SunLight.irradiance:gte=", func(s *pb.Scene) { sun(s).Irradiance = rgb(0, 0, 0) }),
	accept("accept-only-a-point-light", "", func(s *pb.Scene) {
		withoutOtherLights(s)
		s.Shapes[2].Material = "white"
	}),

	accept("accept-only-a-spot-light", "", func(s *pb.Scene) {
		s.Lights, s.Environment = s.Lights[2:], nil
		s.Shapes[2].Material = "white"
	}),
	accept("accept-only-principled-emission", "", func(s *pb.Scene) {
		s.Lights, s.Environment = nil, nil
		s.Shapes[2].Material = "varnish"
	}),
	accept("accept-only-an-instanced-emissive-part", "", func(s *pb.Scene) {
		s.Lights, s.Environment = nil, nil
		s.Shapes[2].Material = "white"
		crate(s).Parts[1].Material = "lamp"
		withInstance(s)
	}),
	accept("accept-only-a-constant-environment", "", func(s *pb.Scene) {
		s.Lights = nil
		s.Shapes[2].Material = "white"
		s.Environment.Map = nil
	}),
	accept("accept-only-an-environment-map", "", func(s *pb.Scene) {
		s.Lights = nil
		s.Shapes[2].Material = "white"
		s.Environment.Radiance = nil
	}),
	accept("accept-spot-light-cones-at-their-bounds", "SpotLight.inner_cone_degrees:lte= SpotLight.outer_cone_degrees:lte=", func(s *pb.Scene) {
		spot(s).InnerConeDegrees, spot(s).OuterConeDegrees = 90, 90
	}),
	accept("accept-spot-light-inner-cone-0", "SpotLight.inner_cone_degrees:gte=", func(s *pb.Scene) { spot(s).InnerConeDegrees = 0 }),
	accept("accept-spot-intensity-0", "SpotLight.intensity:gte=", func(s *pb.Scene) { spot(s).Intensity = rgb(0, 0, 0) }),
	accept("accept-sun-angular-diameter-0", "SunLight.angular_diameter_degrees:gte=", func(s *pb.Scene) { sun(s).AngularDiameterDegrees = 0 }),
	accept("accept-sun-angular-diameter-20", "SunLight.angular_diameter_degrees:lte=", func(s *pb.Scene) { sun(s).AngularDiameterDegrees = 20 }),

	// Principled at its bounds.
	accept("accept-base-color-0-and-1", "Principled.base_color:gte= Principled.base_color:lte=", func(s *pb.Scene) { principled(s).BaseColor = rgb(0, 1, 0.5) }),
	accept("accept-principled-without-base-color", "", func(s *pb.Scene) { principled(s).BaseColor = nil }),
	accept("accept-metallic-0", "Principled.metallic:gte=", func(s *pb.Scene) { principled(s).Metallic = 0 }),
	accept("accept-metallic-1", "Principled.metallic:lte=", func(s *pb.Scene) { principled(s).Metallic = 1 }),
	accept("accept-roughness-0", "Principled.roughness:gte=", func(s *pb.Scene) { principled(s).Roughness = 0 }),
	accept("accept-roughness-1", "Principled.roughness:lte=", func(s *pb.Scene) { principled(s).Roughness = 1 }),
	accept("accept-normal-scale-0", "Principled.normal_scale:gte= Principled.normal_scale:default", func(s *pb.Scene) { principled(s).NormalScale = 0 }),
	accept("accept-normal-scale-10", "Principled.normal_scale:lte=", func(s *pb.Scene) { principled(s).NormalScale = 10 }),
	accept("accept-principled-emission-0-in-one-channel", "Principled.emission:gte=", func(s *pb.Scene) { principled(s).Emission.R = 0 }),
	accept("accept-transparency-0", "Principled.transparency:gte=", func(s *pb.Scene) { principled(s).Transparency = 0 }),
	accept("accept-transparency-1", "Principled.transparency:lte=", func(s *pb.Scene) { principled(s).Transparency = 1 }),
	accept("accept-alpha-cutoff-0", "Principled.alpha_cutoff:gte= Principled.alpha_cutoff:default", func(s *pb.Scene) { principled(s).AlphaCutoff = 0 }),
	accept("accept-alpha-cutoff-1", "Principled.alpha_cutoff:lte=", func(s *pb.Scene) { principled(s).AlphaCutoff = 1 }),

	// Meshes, instances and textures.
	accept("accept-instance", "", func(s *pb.Scene) { withInstance(s) }),
	accept("accept-instance-without-transform", "", func(s *pb.Scene) { withInstance(s).Transform = nil }),
	accept("accept-instance-placed-by-scale-rotation-and-translation", "", func(s *pb.Scene) {
		withInstance(s).Transform = &pb.Transform{Translation: v(1, 0, 0), Scale: v(-1, 2, 1), RotationAxis: v(0, 1, 0), RotationDegrees: 45}
	}),
	accept("accept-mesh-placed-by-a-matrix", "Transform.matrix:max_items=", func(s *pb.Scene) {
		withMesh(s).Transform = &pb.Transform{Matrix: []float64{2, 0, 0, 0, 0, 2, 0, 1, 0, 0, -2, 0}}
	}),
	accept("accept-mesh-name-of-256-bytes", "Mesh.name:max_bytes=", func(s *pb.Scene) {
		crate(s).Name = long(256)
		withInstance(s).Mesh = long(256)
	}),
	accept("accept-mesh-of-1-part", "Mesh.parts:min_items=", func(s *pb.Scene) {
		crate(s).Parts = crate(s).Parts[:1]
		withInstance(s)
	}),
	accept("accept-mesh-of-4096-parts", "Mesh.parts:max_items=", func(s *pb.Scene) { withInstance(s) }, grow("meshes[0].parts", 4096)),
	accept("accept-mesh-part-path-of-4096-bytes", "MeshPart.path:max_bytes=", func(s *pb.Scene) { crate(s).Parts[0].Path = long(4096) }),
	accept("accept-texture-name-of-256-bytes", "Texture.name:max_bytes=", func(s *pb.Scene) {
		s.Textures[1].Name = long(256)
		s.Environment.Map.Texture = long(256)
	}),
	accept("accept-texture-path-of-4096-bytes", "Texture.path:max_bytes=", func(s *pb.Scene) { wood(s).Path = long(4096) }),
	accept("accept-no-meshes-and-no-textures", "", func(s *pb.Scene) {
		s.Meshes, s.Textures, s.Environment = nil, nil, nil
		principled(s).BaseColorTexture, principled(s).MetallicRoughnessTexture = nil, nil
		principled(s).NormalTexture, principled(s).EmissionTexture = nil, nil
	}),

	// The environment, the lens and the output.
	accept("accept-environment-radiance-0-in-one-channel", "Environment.radiance:gte=", func(s *pb.Scene) { s.Environment.Radiance.B = 0 }),
	accept("accept-pinhole-camera", "Camera.aperture_radius:gte= Camera.focus_distance:gte=", func(s *pb.Scene) {
		s.Camera.ApertureRadius, s.Camera.FocusDistance = 0, 0
	}),
	accept("accept-exposure-minus-20-stops", "Output.exposure_stops:gte=", func(s *pb.Scene) { s.Output.ExposureStops = -20 }),
	accept("accept-exposure-20-stops", "Output.exposure_stops:lte=", func(s *pb.Scene) { s.Output.ExposureStops = 20 }),

	// Photon mapping.
	accept("accept-200000000-photons-per-map-in-shards-of-10000000", "PhotonMapping.global_photons:lte= PhotonMapping.caustic_photons:lte= PhotonMapping.photons_per_shard:lte=", func(s *pb.Scene) {
		s.Photons.GlobalPhotons, s.Photons.CausticPhotons, s.Photons.PhotonsPerShard = 200000000, 200000000, 10000000
	}),
	accept("accept-photons-per-shard-1000", "PhotonMapping.photons_per_shard:gte=", func(s *pb.Scene) { s.Photons.PhotonsPerShard = 1000 }),
	accept("accept-10000-shards-per-map", "Scene:max_shards_per_map=", func(s *pb.Scene) {
		s.Photons.GlobalPhotons, s.Photons.CausticPhotons, s.Photons.PhotonsPerShard = 10000000, 9999001, 1000
	}),
	accept("accept-global-photons-0", "PhotonMapping.global_photons:default", func(s *pb.Scene) { s.Photons.GlobalPhotons = 0 }),
	accept("accept-caustic-photons-0", "PhotonMapping.caustic_photons:default", func(s *pb.Scene) { s.Photons.CausticPhotons = 0 }),
	accept("accept-volume-photons-200000000-in-10000-shards", "PhotonMapping.volume_photons:lte=", func(s *pb.Scene) {
		fog(s)
		s.Photons.VolumePhotons, s.Photons.PhotonsPerShard = 200000000, 20000 // max_shards_per_map exactly
	}),
	accept("accept-volume-photons-0", "PhotonMapping.volume_photons:default", func(s *pb.Scene) { fog(s); s.Photons.VolumePhotons = 0 }),
	accept("accept-photons-per-shard-0", "PhotonMapping.photons_per_shard:default", func(s *pb.Scene) { s.Photons.PhotonsPerShard = 0 }),
	accept("accept-no-photon-settings", "", func(s *pb.Scene) { s.Photons = nil }),
	accept("accept-neighbours-10000", "RadianceEstimate.neighbours:lte=", func(s *pb.Scene) { estimate(s).Neighbours = 10000 }),
	accept("accept-max-radius-0", "RadianceEstimate.max_radius:gte=", func(s *pb.Scene) { estimate(s).MaxRadius = 0 }),
	accept("accept-cone-k-1", "RadianceEstimate.cone_k:gte=", func(s *pb.Scene) { estimate(s).ConeK = 1 }),
	accept("accept-cone-k-1000000", "RadianceEstimate.cone_k:lte=", func(s *pb.Scene) { estimate(s).ConeK = 1000000 }),
	accept("accept-cone-k-0", "RadianceEstimate.cone_k:default", func(s *pb.Scene) { estimate(s).ConeK = 0 }),

	// Antialiasing and indirect light.
	accept("accept-antialiasing-mode-unset", "Antialiasing.mode:default", func(s *pb.Scene) { s.Antialiasing.Mode = 0 }),
	accept("accept-edge-samples-1024", "Antialiasing.edge_samples:lte=", func(s *pb.Scene) { s.Antialiasing.EdgeSamples = 1024 }),
	accept("accept-edge-samples-0", "Antialiasing.edge_samples:default", func(s *pb.Scene) { s.Antialiasing.EdgeSamples = 0 }),
	accept("accept-edge-threshold-0", "Antialiasing.edge_threshold:gte= Antialiasing.edge_threshold:default", func(s *pb.Scene) { s.Antialiasing.EdgeThreshold = 0 }),
	accept("accept-indirect-mode-unset", "Indirect.mode:default", func(s *pb.Scene) { s.Indirect.Mode = 0 }),
	accept("accept-specular-sampling-unset", "Sampling.specular:default", func(s *pb.Scene) { s.Sampling.Specular = 0 }),
	accept("accept-adaptive-sampling-unset", "Sampling.adaptive:default", func(s *pb.Scene) { s.Sampling.Adaptive = 0 }),
	accept("accept-spectral-sampling-unset", "Sampling.spectral:default", func(s *pb.Scene) { s.Sampling.Spectral = 0 }),
	accept("accept-spectral-sampling-always", "", func(s *pb.Scene) { s.Sampling.Spectral = pb.SpectralSampling_SPECTRAL_SAMPLING_ALWAYS }),
	accept("accept-gather-rays-4096", "Indirect.gather_rays:lte=", func(s *pb.Scene) { s.Indirect.GatherRays = 4096 }),
	accept("accept-gather-rays-0", "Indirect.gather_rays:default", func(s *pb.Scene) { s.Indirect.GatherRays = 0 }),
	accept("accept-secondary-gather-rays-4096", "Indirect.secondary_gather_rays:lte=", func(s *pb.Scene) { s.Indirect.SecondaryGatherRays = 4096 }),
	accept("accept-secondary-gather-rays-0", "Indirect.secondary_gather_rays:default", func(s *pb.Scene) { s.Indirect.SecondaryGatherRays = 0 }),

	// Progressive rounds.
	accept("accept-max-rounds-1000", "Progressive.max_rounds:lte=", func(s *pb.Scene) { s.Progressive.MaxRounds = 1000 }),
	accept("accept-max-rounds-0", "Progressive.max_rounds:default", func(s *pb.Scene) { s.Progressive.MaxRounds = 0 }),
	accept("accept-target-error-0", "Progressive.target_error:gte=", func(s *pb.Scene) { s.Progressive.TargetError = 0 }),
	accept("accept-time-budget-0", "Progressive.time_budget_seconds:gte=", func(s *pb.Scene) { s.Progressive.TimeBudgetSeconds = 0 }),
	accept("accept-time-budget-of-a-week", "Progressive.time_budget_seconds:lte=", func(s *pb.Scene) { s.Progressive.TimeBudgetSeconds = 604800 }),
	accept("accept-alpha-1", "Progressive.alpha:lte=", func(s *pb.Scene) { s.Progressive.Alpha = 1 }),
	accept("accept-alpha-0", "Progressive.alpha:default", func(s *pb.Scene) { s.Progressive.Alpha = 0 }),
})
