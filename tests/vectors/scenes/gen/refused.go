package main

import (
	"math"
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

var nan, inf = math.NaN(), math.Inf(1)

// badDigest is not a digest (upper-case hex); absentDigest is one of no uploaded file.
const (
	badDigest    = "sha256:0123456789ABCDEF0123456789ABCDEF0123456789ABCDEF0123456789ABCDEF"
	absentDigest = "sha256:0000000000000000000000000000000000000000000000000000000000000000"
)

// refused lists the scenes every side must refuse, each with the field its refusal names.
var refused = slices.Concat(refusedAssets, refusedLooks, refusedFilters, refusedMedia, refusedDispersion, []vectorCase{
	// Scene.
	refuse("refuse-scene-name-of-257-bytes", "name", "Scene.name:max_bytes", func(s *pb.Scene) { s.Name = long(257) }),
	refuse("refuse-no-camera", "camera", "Scene.camera:required", func(s *pb.Scene) { s.Camera = nil }),
	refuse("refuse-no-film", "film", "Scene.film:required", func(s *pb.Scene) { s.Film = nil }),
	refuse("refuse-4097-materials", "materials", "Scene.materials:max_items", unchanged, grow("materials", 4097)),
	refuse("refuse-100001-shapes", "shapes", "Scene.shapes:max_items", unchanged, grow("shapes", 100001)),
	refuse("refuse-4097-lights", "lights", "Scene.lights:max_items", unchanged, grow("lights", 4097)),
	refuse("refuse-no-light", "lights", "Scene.lights:note", func(s *pb.Scene) {
		s.Lights, s.Environment = nil, nil
		s.Shapes[2].Material = "white"
	}),
	refuse("refuse-only-dark-lights", "lights", "Scene.lights:note", func(s *pb.Scene) {
		point(s).Intensity, sun(s).Irradiance, spot(s).Intensity = rgb(0, 0, 0), rgb(0, 0, 0), rgb(0, 0, 0)
		emissive(s).Radiance = rgb(0, 0, 0)
		s.Environment.Radiance = rgb(0, 0, 0) // its map times black
	}),
	refuse("refuse-only-a-black-principled-emission", "lights", "Scene.lights:note", func(s *pb.Scene) {
		s.Lights, s.Environment = nil, nil
		s.Shapes[2].Material = "varnish"
		principled(s).Emission = rgb(0, 0, 0)
	}),
	refuse("refuse-only-an-instanced-part-of-black-emission", "lights", "Scene.lights:note", func(s *pb.Scene) {
		s.Lights, s.Environment = nil, nil
		emissive(s).Radiance = rgb(0, 0, 0)
		crate(s).Parts[0].Material = "lamp"
		withInstance(s)
	}),

	// Camera.
	refuse("refuse-camera-without-position", "camera.position", "Camera.position:required", func(s *pb.Scene) { s.Camera.Position = nil }),
	refuse("refuse-camera-without-look-at", "camera.look_at", "Camera.look_at:required", func(s *pb.Scene) { s.Camera.LookAt = nil }),
	refuse("refuse-camera-without-up", "camera.up", "Camera.up:required", func(s *pb.Scene) { s.Camera.Up = nil }),
	refuse("refuse-camera-look-at-its-position", "camera.look_at", "Camera.look_at:note", func(s *pb.Scene) { s.Camera.LookAt = v(0, 1, 5) }),
	refuse("refuse-camera-up-zero", "camera.up", "Camera.up:note", func(s *pb.Scene) { s.Camera.Up = v(0, 0, 0) }),
	refuse("refuse-camera-up-along-the-view", "camera.up", "Camera.up:note", func(s *pb.Scene) { s.Camera.Up = v(0, 0, -3) }),
	refuse("refuse-fov-0", "camera.vertical_fov_degrees", "Camera.vertical_fov_degrees:gt", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 0 }),
	refuse("refuse-fov-180", "camera.vertical_fov_degrees", "Camera.vertical_fov_degrees:lt", func(s *pb.Scene) { s.Camera.VerticalFovDegrees = 180 }),

	// Vec3 components, in various places.
	refuse("refuse-camera-position-x-nan", "camera.position.x", "Vec3.x:nan", func(s *pb.Scene) { s.Camera.Position.X = nan }),
	refuse("refuse-quad-origin-x-infinite", "shapes[1].quad.origin.x", "Vec3.x:inf", func(s *pb.Scene) { quad(s).Origin.X = inf }),
	refuse("refuse-point-position-x-past-max-magnitude", "lights[0].point.position.x", "Vec3.x:magnitude", func(s *pb.Scene) { point(s).Position.X = 2e12 }),
	refuse("refuse-sphere-center-y-nan", "shapes[0].sphere.center.y", "Vec3.y:nan", func(s *pb.Scene) { sphere(s).Center.Y = nan }),
	refuse("refuse-camera-look-at-y-minus-infinity", "camera.look_at.y", "Vec3.y:inf", func(s *pb.Scene) { s.Camera.LookAt.Y = -inf }),
	refuse("refuse-triangle-position-y-past-max-magnitude", "shapes[3].triangles.positions[1].y", "Vec3.y:magnitude", func(s *pb.Scene) { triangles(s).Positions[1].Y = -3e12 }),
	refuse("refuse-sun-direction-z-nan", "lights[1].sun.direction.z", "Vec3.z:nan", func(s *pb.Scene) { sun(s).Direction.Z = nan }),
	refuse("refuse-camera-up-z-infinite", "camera.up.z", "Vec3.z:inf", func(s *pb.Scene) { s.Camera.Up.Z = inf }),
	refuse("refuse-quad-edge-v-z-past-max-magnitude", "shapes[1].quad.edge_v.z", "Vec3.z:magnitude", func(s *pb.Scene) { quad(s).EdgeV.Z = 1e13 }),

	// Color components, in various places.
	refuse("refuse-lambert-reflectance-r-nan", "materials[0].lambert.reflectance.r", "Color.r:nan", func(s *pb.Scene) { lambert(s).Reflectance.R = nan }),
	refuse("refuse-emissive-radiance-r-infinite", "materials[1].emissive.radiance.r", "Color.r:inf", func(s *pb.Scene) { emissive(s).Radiance.R = inf }),
	refuse("refuse-emissive-radiance-r-past-max-magnitude", "materials[1].emissive.radiance.r", "Color.r:magnitude", func(s *pb.Scene) { emissive(s).Radiance.R = 2e12 }),
	refuse("refuse-point-intensity-g-nan", "lights[0].point.intensity.g", "Color.g:nan", func(s *pb.Scene) { point(s).Intensity.G = nan }),
	refuse("refuse-sun-irradiance-g-infinite", "lights[1].sun.irradiance.g", "Color.g:inf", func(s *pb.Scene) { sun(s).Irradiance.G = inf }),
	refuse("refuse-point-intensity-g-past-max-magnitude", "lights[0].point.intensity.g", "Color.g:magnitude", func(s *pb.Scene) { point(s).Intensity.G = -2e12 }),
	refuse("refuse-conductor-k-b-nan", "materials[5].conductor.k.b", "Color.b:nan", func(s *pb.Scene) { conductor(s).K.B = nan }),
	refuse("refuse-dielectric-transmittance-b-minus-infinity", "materials[4].dielectric.transmittance.b", "Color.b:inf", func(s *pb.Scene) { dielectric(s).Transmittance.B = -inf }),
	refuse("refuse-glossy-specular-b-past-max-magnitude", "materials[2].glossy.specular.b", "Color.b:magnitude", func(s *pb.Scene) { glossy(s).Specular.B = 5e12 }),

	// Film.
	refuse("refuse-film-width-0", "film.width", "Film.width:gte", func(s *pb.Scene) { s.Film.Width = 0 }),
	refuse("refuse-film-width-16385", "film.width", "Film.width:lte", func(s *pb.Scene) { s.Film.Width = 16385 }),
	refuse("refuse-film-height-0", "film.height", "Film.height:gte", func(s *pb.Scene) { s.Film.Height = 0 }),
	refuse("refuse-film-height-16385", "film.height", "Film.height:lte", func(s *pb.Scene) { s.Film.Height = 16385 }),
	refuse("refuse-tile-size-7", "film.tile_size", "Film.tile_size:gte", func(s *pb.Scene) { s.Film.TileSize = 7 }),
	refuse("refuse-tile-size-257", "film.tile_size", "Film.tile_size:lte", func(s *pb.Scene) { s.Film.TileSize = 257 }),
	refuse("refuse-262144-tiles-per-round", "film.tile_size", "Film.tile_size:note", func(s *pb.Scene) {
		s.Film.Width, s.Film.Height, s.Film.TileSize = 16384, 16384, 32
	}),
	refuse("refuse-film-of-one-row-more-than-the-pixel-limit", "film.height", "Film.height:note", func(s *pb.Scene) {
		s.Film.Width, s.Film.Height, s.Film.TileSize = 16384, 513, 256
	}),
	refuse("refuse-65792-tiles-per-round-at-the-default-tile-size", "film.tile_size", "Film.tile_size:note", func(s *pb.Scene) {
		// ceil(8193 / 32) · (8192 / 32) = 257 · 256 tiles of the default 32 pixels; one
		// pixel less wide is exactly the limit (accepted).
		s.Film.Width, s.Film.Height, s.Film.TileSize = 8193, 8192, 0
	}),

	// Sampling.
	refuse("refuse-samples-per-pixel-65537", "sampling.samples_per_pixel", "Sampling.samples_per_pixel:lte", func(s *pb.Scene) { s.Sampling.SamplesPerPixel = 65537 }),
	refuse("refuse-light-samples-1025", "sampling.light_samples", "Sampling.light_samples:lte", func(s *pb.Scene) { s.Sampling.LightSamples = 1025 }),

	// Materials.
	refuse("refuse-material-without-name", "materials[0].name", "Material.name:required", func(s *pb.Scene) { s.Materials[0].Name = "" }),
	refuse("refuse-material-name-of-257-bytes", "materials[3].name", "Material.name:max_bytes", func(s *pb.Scene) { s.Materials[3].Name = long(257) }),
	refuse("refuse-duplicate-material-name", "materials[4].name", "Material.name:note", func(s *pb.Scene) { s.Materials[4].Name = "white" }),
	refuse("refuse-material-without-kind", "materials[3]", "Material.kind:one_required", func(s *pb.Scene) { s.Materials[3].Kind = nil }),
	refuse("refuse-lambert-without-reflectance", "materials[0].lambert.reflectance", "Lambert.reflectance:required", func(s *pb.Scene) { lambert(s).Reflectance = nil }),
	refuse("refuse-lambert-reflectance-below-0", "materials[0].lambert.reflectance.b", "Lambert.reflectance:gte", func(s *pb.Scene) { lambert(s).Reflectance.B = -0.1 }),
	refuse("refuse-lambert-reflectance-above-1", "materials[0].lambert.reflectance.g", "Lambert.reflectance:lte", func(s *pb.Scene) { lambert(s).Reflectance.G = 1.1 }),
	refuse("refuse-emissive-without-radiance", "materials[1].emissive.radiance", "Emissive.radiance:required", func(s *pb.Scene) { emissive(s).Radiance = nil }),
	refuse("refuse-emissive-radiance-below-0", "materials[1].emissive.radiance.g", "Emissive.radiance:gte", func(s *pb.Scene) { emissive(s).Radiance.G = -1 }),
	refuse("refuse-emissive-reflectance-below-0", "materials[1].emissive.reflectance.r", "Emissive.reflectance:gte", func(s *pb.Scene) { emissive(s).Reflectance = rgb(-0.1, 0.5, 0.5) }),
	refuse("refuse-emissive-reflectance-above-1", "materials[1].emissive.reflectance.b", "Emissive.reflectance:lte", func(s *pb.Scene) { emissive(s).Reflectance = rgb(0.5, 0.5, 1.1) }),
	refuse("refuse-glossy-without-diffuse", "materials[2].glossy.diffuse", "Glossy.diffuse:required", func(s *pb.Scene) { glossy(s).Diffuse = nil }),
	refuse("refuse-glossy-diffuse-below-0", "materials[2].glossy.diffuse.g", "Glossy.diffuse:gte", func(s *pb.Scene) { glossy(s).Diffuse.G = -0.25 }),
	refuse("refuse-glossy-diffuse-above-1", "materials[2].glossy.diffuse.r", "Glossy.diffuse:lte", func(s *pb.Scene) { glossy(s).Diffuse.R = 1.2 }),
	refuse("refuse-glossy-without-specular", "materials[2].glossy.specular", "Glossy.specular:required", func(s *pb.Scene) { glossy(s).Specular = nil }),
	refuse("refuse-glossy-specular-below-0", "materials[2].glossy.specular.r", "Glossy.specular:gte", func(s *pb.Scene) { glossy(s).Specular.R = -0.5 }),
	refuse("refuse-glossy-specular-above-1", "materials[2].glossy.specular.g", "Glossy.specular:lte", func(s *pb.Scene) { glossy(s).Specular.G = 1.5 }),
	refuse("refuse-glossy-red-reflects-more-than-it-receives", "materials[2].glossy.specular.r", "Glossy.specular:note", func(s *pb.Scene) { glossy(s).Diffuse.R = 0.6 }),
	refuse("refuse-glossy-green-reflects-more-than-it-receives", "materials[2].glossy.specular.g", "Glossy.specular:note", func(s *pb.Scene) { glossy(s).Specular.G = 0.7 }),
	refuse("refuse-glossy-blue-reflects-more-than-it-receives", "materials[2].glossy.specular.b", "Glossy.specular:note", func(s *pb.Scene) { glossy(s).Diffuse.B = 0.5000001 }),
	refuse("refuse-glossy-exponent-below-1", "materials[2].glossy.exponent", "Glossy.exponent:gte", func(s *pb.Scene) { glossy(s).Exponent = 0.5 }),
	refuse("refuse-glossy-exponent-100001", "materials[2].glossy.exponent", "Glossy.exponent:lte", func(s *pb.Scene) { glossy(s).Exponent = 100001 }),
	refuse("refuse-mirror-without-reflectance", "materials[3].mirror.reflectance", "Mirror.reflectance:required", func(s *pb.Scene) { mirror(s).Reflectance = nil }),
	refuse("refuse-mirror-reflectance-below-0", "materials[3].mirror.reflectance.r", "Mirror.reflectance:gte", func(s *pb.Scene) { mirror(s).Reflectance.R = -0.5 }),
	refuse("refuse-mirror-reflectance-above-1", "materials[3].mirror.reflectance.b", "Mirror.reflectance:lte", func(s *pb.Scene) { mirror(s).Reflectance.B = 1.01 }),
	refuse("refuse-ior-below-1", "materials[4].dielectric.ior", "Dielectric.ior:gte", func(s *pb.Scene) { dielectric(s).Ior = 0.99 }),
	refuse("refuse-ior-0", "materials[4].dielectric.ior", "Dielectric.ior:gte", func(s *pb.Scene) { dielectric(s).Ior = 0 }),
	refuse("refuse-ior-above-10", "materials[4].dielectric.ior", "Dielectric.ior:lte", func(s *pb.Scene) { dielectric(s).Ior = 10.5 }),
	refuse("refuse-transmittance-below-0", "materials[4].dielectric.transmittance.g", "Dielectric.transmittance:gte", func(s *pb.Scene) { dielectric(s).Transmittance.G = -0.1 }),
	refuse("refuse-transmittance-above-1", "materials[4].dielectric.transmittance.r", "Dielectric.transmittance:lte", func(s *pb.Scene) { dielectric(s).Transmittance.R = 1.5 }),
	refuse("refuse-conductor-without-eta", "materials[5].conductor.eta", "Conductor.eta:required", func(s *pb.Scene) { conductor(s).Eta = nil }),
	refuse("refuse-conductor-eta-0", "materials[5].conductor.eta.g", "Conductor.eta:gt", func(s *pb.Scene) { conductor(s).Eta.G = 0 }),
	refuse("refuse-conductor-eta-above-100", "materials[5].conductor.eta.r", "Conductor.eta:lte", func(s *pb.Scene) { conductor(s).Eta.R = 200 }),
	refuse("refuse-conductor-without-k", "materials[5].conductor.k", "Conductor.k:required", func(s *pb.Scene) { conductor(s).K = nil }),
	refuse("refuse-conductor-k-below-0", "materials[5].conductor.k.b", "Conductor.k:gte", func(s *pb.Scene) { conductor(s).K.B = -1 }),
	refuse("refuse-conductor-k-above-100", "materials[5].conductor.k.r", "Conductor.k:lte", func(s *pb.Scene) { conductor(s).K.R = 500 }),

	// Shapes.
	refuse("refuse-shape-name-of-257-bytes", "shapes[2].name", "Shape.name:max_bytes", func(s *pb.Scene) { s.Shapes[2].Name = long(257) }),
	refuse("refuse-shape-without-material", "shapes[0].material", "Shape.material:note", func(s *pb.Scene) { s.Shapes[0].Material = "" }),
	refuse("refuse-shape-of-unknown-material", "shapes[4].material", "Shape.material:note", func(s *pb.Scene) { s.Shapes[4].Material = "chrome" }),
	refuse("refuse-shape-without-geometry", "shapes[2]", "Shape.geometry:one_required", func(s *pb.Scene) { s.Shapes[2].Geometry = nil }),
	refuse("refuse-sphere-without-center", "shapes[0].sphere.center", "Sphere.center:required", func(s *pb.Scene) { sphere(s).Center = nil }),
	refuse("refuse-sphere-radius-0", "shapes[0].sphere.radius", "Sphere.radius:gt", func(s *pb.Scene) { sphere(s).Radius = 0 }),
	refuse("refuse-sphere-radius-negative", "shapes[0].sphere.radius", "Sphere.radius:gt", func(s *pb.Scene) { sphere(s).Radius = -1 }),
	refuse("refuse-quad-without-origin", "shapes[1].quad.origin", "Quad.origin:required", func(s *pb.Scene) { quad(s).Origin = nil }),
	refuse("refuse-quad-without-edge-u", "shapes[1].quad.edge_u", "Quad.edge_u:required", func(s *pb.Scene) { quad(s).EdgeU = nil }),
	refuse("refuse-quad-edge-u-zero", "shapes[1].quad.edge_u", "Quad.edge_u:note", func(s *pb.Scene) { quad(s).EdgeU = v(0, 0, 0) }),
	refuse("refuse-quad-without-edge-v", "shapes[1].quad.edge_v", "Quad.edge_v:required", func(s *pb.Scene) { quad(s).EdgeV = nil }),
	refuse("refuse-quad-edge-v-zero", "shapes[1].quad.edge_v", "Quad.edge_v:note", func(s *pb.Scene) { quad(s).EdgeV = v(0, 0, 0) }),
	refuse("refuse-quad-edges-parallel", "shapes[1].quad.edge_v", "Quad.edge_v:note", func(s *pb.Scene) { quad(s).EdgeV = v(-2, 0, 0) }),
	refuse("refuse-triangles-with-2-positions", "shapes[3].triangles.positions", "TriangleMesh.positions:min_items", func(s *pb.Scene) {
		triangles(s).Positions = triangles(s).Positions[:2]
	}),
	refuse("refuse-triangles-with-1000001-positions", "shapes[3].triangles.positions", "TriangleMesh.positions:max_items", unchanged,
		grow("shapes[3].triangles.positions", 1000001)),
	refuse("refuse-triangles-with-3000001-indices", "shapes[3].triangles.indices", "TriangleMesh.indices:max_items", unchanged,
		grow("shapes[3].triangles.indices", 3000001)),
	refuse("refuse-triangles-with-no-indices", "shapes[3].triangles.indices", "TriangleMesh.indices:note", func(s *pb.Scene) { triangles(s).Indices = nil }),
	refuse("refuse-triangles-with-4-indices", "shapes[3].triangles.indices", "TriangleMesh.indices:note", func(s *pb.Scene) {
		triangles(s).Indices = []uint32{0, 1, 2, 0}
	}),
	refuse("refuse-triangle-index-past-the-positions", "shapes[3].triangles.indices[4]", "TriangleMesh.indices:note", func(s *pb.Scene) {
		triangles(s).Indices = []uint32{0, 1, 2, 2, 3, 0}
	}),
	refuse("refuse-mesh-path-of-4097-bytes", "shapes[7].mesh.path", "MeshFile.path:max_bytes", func(s *pb.Scene) { withMesh(s).Path = long(4097) }),
	refuse("refuse-mesh-without-digest", "shapes[7].mesh.digest", "MeshFile.digest:required", func(s *pb.Scene) {
		m := withMesh(s)
		m.Path, m.Digest = "", ""
	}),
	refuse("refuse-mesh-path-not-uploaded", "shapes[7].mesh.digest", "MeshFile.digest:required", func(s *pb.Scene) { withMesh(s).Digest = "" }),
	refuse("refuse-mesh-digest-malformed", "shapes[7].mesh.digest", "MeshFile.digest:digest", func(s *pb.Scene) { withMesh(s).Digest = badDigest }),
	refuse("refuse-mesh-of-no-uploaded-file", "shapes[7].mesh.digest", "MeshFile.digest:note", func(s *pb.Scene) { withMesh(s).Digest = absentDigest }),
	refuse("refuse-mesh-scale-x-0", "shapes[7].mesh.transform.scale.x", "Transform.scale:note", func(s *pb.Scene) { withMesh(s).Transform.Scale.X = 0 }),
	refuse("refuse-mesh-scale-y-0", "shapes[7].mesh.transform.scale.y", "Transform.scale:note", func(s *pb.Scene) { withMesh(s).Transform.Scale.Y = 0 }),
	refuse("refuse-mesh-scale-z-0", "shapes[7].mesh.transform.scale.z", "Transform.scale:note", func(s *pb.Scene) { withMesh(s).Transform.Scale.Z = 0 }),
	refuse("refuse-mesh-rotation-about-zero-axis", "shapes[7].mesh.transform.rotation_axis", "Transform.rotation_axis:note", func(s *pb.Scene) {
		withMesh(s).Transform.RotationAxis = v(0, 0, 0)
	}),
	refuse("refuse-mesh-rotation-without-axis", "shapes[7].mesh.transform.rotation_axis", "Transform.rotation_axis:note", func(s *pb.Scene) {
		withMesh(s).Transform.RotationAxis = nil
	}),

	// Lights.
	refuse("refuse-light-name-of-257-bytes", "lights[1].name", "Light.name:max_bytes", func(s *pb.Scene) { s.Lights[1].Name = long(257) }),
	refuse("refuse-light-without-kind", "lights[0]", "Light.kind:one_required", func(s *pb.Scene) { s.Lights[0].Kind = nil }),
	refuse("refuse-point-light-without-position", "lights[0].point.position", "PointLight.position:required", func(s *pb.Scene) { point(s).Position = nil }),
	refuse("refuse-point-light-without-intensity", "lights[0].point.intensity", "PointLight.intensity:required", func(s *pb.Scene) { point(s).Intensity = nil }),
	refuse("refuse-point-intensity-below-0", "lights[0].point.intensity.b", "PointLight.intensity:gte", func(s *pb.Scene) { point(s).Intensity.B = -1 }),
	refuse("refuse-sun-without-direction", "lights[1].sun.direction", "SunLight.direction:required", func(s *pb.Scene) { sun(s).Direction = nil }),
	refuse("refuse-sun-direction-zero", "lights[1].sun.direction", "SunLight.direction:note", func(s *pb.Scene) { sun(s).Direction = v(0, 0, 0) }),
	refuse("refuse-sun-without-irradiance", "lights[1].sun.irradiance", "SunLight.irradiance:required", func(s *pb.Scene) { sun(s).Irradiance = nil }),
	refuse("refuse-sun-irradiance-below-0", "lights[1].sun.irradiance.r", "SunLight.irradiance:gte", func(s *pb.Scene) { sun(s).Irradiance.R = -0.5 }),

	// Photon mapping.
	refuse("refuse-global-photons-200000001", "photons.global_photons", "PhotonMapping.global_photons:lte", func(s *pb.Scene) { s.Photons.GlobalPhotons = 200000001 }),
	refuse("refuse-caustic-photons-200000001", "photons.caustic_photons", "PhotonMapping.caustic_photons:lte", func(s *pb.Scene) { s.Photons.CausticPhotons = 200000001 }),
	refuse("refuse-volume-photons-200000001", "photons.volume_photons", "PhotonMapping.volume_photons:lte", func(s *pb.Scene) { s.Photons.VolumePhotons = 200000001 }),
	refuse("refuse-photons-per-shard-999", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:gte", func(s *pb.Scene) { s.Photons.PhotonsPerShard = 999 }),
	refuse("refuse-photons-per-shard-10000001", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:lte", func(s *pb.Scene) { s.Photons.PhotonsPerShard = 10000001 }),
	refuse("refuse-global-map-of-20000-shards", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:note", func(s *pb.Scene) {
		s.Photons.GlobalPhotons, s.Photons.PhotonsPerShard = 20000000, 1000
	}),
	refuse("refuse-caustic-map-of-10001-shards", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:note", func(s *pb.Scene) {
		s.Photons.CausticPhotons, s.Photons.PhotonsPerShard = 10000001, 1000
	}),
	refuse("refuse-caustic-photons-past-the-shard-limit-without-a-specular-surface", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:note", func(s *pb.Scene) {
		// The limit is on the settings: both counts, whether or not the scene gets the map.
		withoutSpecular(s)
		s.Photons.CausticPhotons, s.Photons.PhotonsPerShard = 50000000, 1000
	}),
	refuse("refuse-volume-map-of-10001-shards", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:note", func(s *pb.Scene) {
		fog(s)
		s.Photons.VolumePhotons, s.Photons.PhotonsPerShard = 10000001, 1000
	}),
	refuse("refuse-volume-photons-past-the-shard-limit-without-a-medium", "photons.photons_per_shard", "PhotonMapping.photons_per_shard:note", func(s *pb.Scene) {
		// Like the caustic count, the volume count is bounded whether or not the scene gets the map.
		s.Photons.VolumePhotons, s.Photons.PhotonsPerShard = 50000000, 1000
	}),
	refuse("refuse-neighbours-10001", "photons.global_estimate.neighbours", "RadianceEstimate.neighbours:lte", func(s *pb.Scene) { estimate(s).Neighbours = 10001 }),
	refuse("refuse-max-radius-negative", "photons.caustic_estimate.max_radius", "RadianceEstimate.max_radius:gte", func(s *pb.Scene) { s.Photons.CausticEstimate.MaxRadius = -1 }),
	refuse("refuse-volume-estimate-neighbours-10001", "photons.volume_estimate.neighbours", "RadianceEstimate.neighbours:lte", func(s *pb.Scene) {
		fog(s)
		s.Photons.VolumeEstimate = &pb.RadianceEstimate{Neighbours: 10001}
	}),
	refuse("refuse-unknown-filter", "photons.caustic_estimate.filter", "RadianceEstimate.filter:enum", func(s *pb.Scene) { s.Photons.CausticEstimate.Filter = 9 }),
	refuse("refuse-cone-k-below-1", "photons.global_estimate.cone_k", "RadianceEstimate.cone_k:gte", func(s *pb.Scene) { estimate(s).ConeK = 0.5 }),
	refuse("refuse-cone-k-1000001", "photons.global_estimate.cone_k", "RadianceEstimate.cone_k:lte", func(s *pb.Scene) { estimate(s).ConeK = 1000001 }),

	// Antialiasing and indirect light.
	refuse("refuse-unknown-antialiasing-mode", "antialiasing.mode", "Antialiasing.mode:enum", func(s *pb.Scene) { s.Antialiasing.Mode = 7 }),
	refuse("refuse-edge-samples-1025", "antialiasing.edge_samples", "Antialiasing.edge_samples:lte", func(s *pb.Scene) { s.Antialiasing.EdgeSamples = 1025 }),
	refuse("refuse-edge-threshold-negative", "antialiasing.edge_threshold", "Antialiasing.edge_threshold:gte", func(s *pb.Scene) { s.Antialiasing.EdgeThreshold = -0.1 }),
	refuse("refuse-unknown-indirect-mode", "indirect.mode", "Indirect.mode:enum", func(s *pb.Scene) { s.Indirect.Mode = 5 }),
	refuse("refuse-unknown-specular-sampling", "sampling.specular", "Sampling.specular:enum", func(s *pb.Scene) { s.Sampling.Specular = 6 }),
	refuse("refuse-unknown-adaptive-sampling", "sampling.adaptive", "Sampling.adaptive:enum", func(s *pb.Scene) { s.Sampling.Adaptive = 7 }),
	refuse("refuse-unknown-spectral-sampling", "sampling.spectral", "Sampling.spectral:enum", func(s *pb.Scene) { s.Sampling.Spectral = 3 }),
	refuse("refuse-gather-rays-4097", "indirect.gather_rays", "Indirect.gather_rays:lte", func(s *pb.Scene) { s.Indirect.GatherRays = 4097 }),
	refuse("refuse-secondary-gather-rays-4097", "indirect.secondary_gather_rays", "Indirect.secondary_gather_rays:lte", func(s *pb.Scene) { s.Indirect.SecondaryGatherRays = 4097 }),

	// Progressive rounds.
	refuse("refuse-max-rounds-1001", "progressive.max_rounds", "Progressive.max_rounds:lte", func(s *pb.Scene) { s.Progressive.MaxRounds = 1001 }),
	refuse("refuse-target-error-negative", "progressive.target_error", "Progressive.target_error:gte", func(s *pb.Scene) { s.Progressive.TargetError = -0.01 }),
	refuse("refuse-time-budget-negative", "progressive.time_budget_seconds", "Progressive.time_budget_seconds:gte", func(s *pb.Scene) { s.Progressive.TimeBudgetSeconds = -1 }),
	refuse("refuse-time-budget-over-a-week", "progressive.time_budget_seconds", "Progressive.time_budget_seconds:lte", func(s *pb.Scene) { s.Progressive.TimeBudgetSeconds = 604801 }),
	refuse("refuse-alpha-negative", "progressive.alpha", "Progressive.alpha:gt", func(s *pb.Scene) { s.Progressive.Alpha = -0.5 }),
	refuse("refuse-alpha-above-1", "progressive.alpha", "Progressive.alpha:lte", func(s *pb.Scene) { s.Progressive.Alpha = 1.5 }),
	refuse("refuse-reference-path-of-4097-bytes", "progressive.reference.path", "ReferenceImage.path:max_bytes", func(s *pb.Scene) {
		s.Progressive.Reference = &pb.ReferenceImage{Path: long(4097), Digest: absentDigest}
	}),
	refuse("refuse-reference-digest-malformed", "progressive.reference.digest", "ReferenceImage.digest:digest", func(s *pb.Scene) {
		s.Progressive.Reference = &pb.ReferenceImage{Path: "reference.exr", Digest: badDigest}
	}),
	refuse("refuse-reference-path-not-uploaded", "progressive.reference.digest", "ReferenceImage.digest:note", func(s *pb.Scene) {
		s.Progressive.Reference = &pb.ReferenceImage{Path: "reference.exr"}
	}),
	refuse("refuse-sphere-radius-just-past-max-magnitude", "shapes[0].sphere.radius", "Sphere.radius:magnitude", func(s *pb.Scene) { sphere(s).Radius = 1.0000001e12 }),
},
	// Doubles with a rule of their own (those of vectors and colours are above, in
	// various places), each NaN, infinite and past max_magnitude.
	nonFinite("refuse-fov", "camera.vertical_fov_degrees", "Camera.vertical_fov_degrees", func(s *pb.Scene, x float64) { s.Camera.VerticalFovDegrees = x }),
	nonFinite("refuse-glossy-exponent", "materials[2].glossy.exponent", "Glossy.exponent", func(s *pb.Scene, x float64) { glossy(s).Exponent = x }),
	nonFinite("refuse-ior", "materials[4].dielectric.ior", "Dielectric.ior", func(s *pb.Scene, x float64) { dielectric(s).Ior = x }),
	nonFinite("refuse-sphere-radius", "shapes[0].sphere.radius", "Sphere.radius", func(s *pb.Scene, x float64) { sphere(s).Radius = x }),
	nonFinite("refuse-mesh-rotation", "shapes[7].mesh.transform.rotation_degrees", "Transform.rotation_degrees", func(s *pb.Scene, x float64) {
		withMesh(s).Transform.RotationDegrees = x
	}),
	nonFinite("refuse-max-radius", "photons.global_estimate.max_radius", "RadianceEstimate.max_radius", func(s *pb.Scene, x float64) { estimate(s).MaxRadius = x }),
	nonFinite("refuse-cone-k", "photons.global_estimate.cone_k", "RadianceEstimate.cone_k", func(s *pb.Scene, x float64) { estimate(s).ConeK = x }),
	nonFinite("refuse-edge-threshold", "antialiasing.edge_threshold", "Antialiasing.edge_threshold", func(s *pb.Scene, x float64) { s.Antialiasing.EdgeThreshold = x }),
	nonFinite("refuse-target-error", "progressive.target_error", "Progressive.target_error", func(s *pb.Scene, x float64) { s.Progressive.TargetError = x }),
	nonFinite("refuse-time-budget", "progressive.time_budget_seconds", "Progressive.time_budget_seconds", func(s *pb.Scene, x float64) { s.Progressive.TimeBudgetSeconds = x }),
	nonFinite("refuse-alpha", "progressive.alpha", "Progressive.alpha", func(s *pb.Scene, x float64) { s.Progressive.Alpha = x }),
)
