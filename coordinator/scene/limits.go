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
	DefaultSamplesPerPixel = 16
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
)
