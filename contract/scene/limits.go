package scene

// Limits on scenes. They are documented for users in docs/limits.md; keep the two in step.
const (
	// MaxFilmSide is the largest film width or height, in pixels.
	MaxFilmSide = 16384
	// MinTileSize and MaxTileSize bound Film.tile_size when it is not 0.
	MinTileSize = 8
	MaxTileSize = 256
	// DefaultTileSize is used when Film.tile_size is 0.
	DefaultTileSize = 32
	// MaxSamplesPerPixel bounds Sampling.samples_per_pixel.
	MaxSamplesPerPixel = 65536
	// DefaultSamplesPerPixel is used when Sampling.samples_per_pixel is 0.
	DefaultSamplesPerPixel = 1
	// MaxMaterials and MaxShapes bound the scene's lists.
	MaxMaterials = 4096
	MaxShapes    = 100000
	// MaxMeshPositions and MaxMeshIndices bound one inline TriangleMesh.
	MaxMeshPositions = 1000000
	MaxMeshIndices   = 3 * MaxMeshPositions
	// MaxNameLength bounds the scene, material and shape names, in bytes.
	MaxNameLength = 256
	// MaxCoordinate bounds the magnitude of every coordinate, radius and scale.
	MaxCoordinate = 1e12
	// MaxLights bounds Scene.lights (point and sun lights).
	MaxLights = 4096

	// MinGlossyExponent and MaxGlossyExponent bound Glossy.exponent.
	MinGlossyExponent = 1
	MaxGlossyExponent = 1e5
	// MinIOR and MaxIOR bound Dielectric.ior.
	MinIOR = 1
	MaxIOR = 10

	// MaxPhotonsPerMap bounds PhotonMapping.global_photons and caustic_photons.
	MaxPhotonsPerMap = 50_000_000
	// DefaultGlobalPhotons and DefaultCausticPhotons are used when the counts are 0.
	DefaultGlobalPhotons  = 200_000
	DefaultCausticPhotons = 200_000
	// MinPhotonsPerShard and MaxPhotonsPerShard bound PhotonMapping.photons_per_shard when
	// it is not 0; DefaultPhotonsPerShard is used when it is.
	MinPhotonsPerShard     = 1000
	MaxPhotonsPerShard     = 10_000_000
	DefaultPhotonsPerShard = 100_000
	// MaxNeighbours bounds RadianceEstimate.neighbours.
	MaxNeighbours = 10000
	// MaxConeK bounds RadianceEstimate.cone_k (a cone filter's k >= 1; past this it is a box).
	MaxConeK = 1e6

	// MaxPathLength bounds the file paths a scene file names (meshes, reference image).
	MaxPathLength = 4096

	// MaxLightSamples bounds Sampling.light_samples; DefaultLightSamples is used for 0.
	MaxLightSamples     = 1024
	DefaultLightSamples = 16
	// MaxEdgeSamples bounds Antialiasing.edge_samples; DefaultEdgeSamples is used for 0.
	MaxEdgeSamples     = 1024
	DefaultEdgeSamples = 12
	// DefaultEdgeThreshold is used when Antialiasing.edge_threshold is 0.
	DefaultEdgeThreshold = 0.1
	// MaxGatherRays bounds Indirect.gather_rays and secondary_gather_rays.
	MaxGatherRays              = 4096
	DefaultGatherRays          = 64
	DefaultSecondaryGatherRays = 8
	// MaxRounds bounds Progressive.max_rounds.
	MaxRounds = 1000
	// MaxTimeBudgetSeconds bounds Progressive.time_budget_seconds (7 days).
	MaxTimeBudgetSeconds = 7 * 24 * 3600
	// DefaultAlpha is progressive photon mapping's alpha when Progressive.alpha is 0.
	DefaultAlpha = 0.7
)
