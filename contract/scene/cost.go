package scene

import (
	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// The planner makes a task per tile and per emission shard of every round, so two limits
// (scene.proto's scene_limits) bound the cost of planning a round and the size of the
// requests that list its tasks; a third, the film's pixels, the cost of its composite.

// TilesPerRound returns how many render tiles one round of s has: ceil(width / t) ·
// ceil(height / t) for the effective tile size t.
func TilesPerRound(s *pb.Scene) uint64 {
	t := uint64(TileSize(s))
	w, h := uint64(s.GetFilm().GetWidth()), uint64(s.GetFilm().GetHeight())
	return ceilDiv(w, t) * ceilDiv(h, t)
}

// ShardsPerMap returns how many emission shards a photon map of the given number of paths
// has in one round of s.
func ShardsPerMap(s *pb.Scene, photons uint64) uint64 { return ceilDiv(photons, PhotonsPerShard(s)) }

// checkTiles: at most max_tiles_per_round tiles (film.tile_size).
func checkTiles(s *pb.Scene) *FieldError {
	if n, limit := TilesPerRound(s), rules.Scene.GetMaxTilesPerRound(); n > limit {
		f := s.GetFilm()
		return rules.Errorf("film.tile_size", "%d-pixel tiles (film.tile_size) make %d tiles of a %dx%d film (film.width x film.height) per round, more than max_tiles_per_round, %d: use larger tiles or a smaller film",
			TileSize(s), n, f.GetWidth(), f.GetHeight(), limit)
	}
	return nil
}

// checkPixels: at most max_film_pixels pixels (film.height): the composite's memory and the
// size of the image it makes.
func checkPixels(s *pb.Scene) *FieldError {
	f := s.GetFilm()
	if n, limit := uint64(f.GetWidth())*uint64(f.GetHeight()), rules.Scene.GetMaxFilmPixels(); n > limit {
		return rules.Errorf("film.height", "a %dx%d film has %d pixels, more than %d: make it smaller", f.GetWidth(), f.GetHeight(), n, limit)
	}
	return nil
}

// checkShards: at most max_shards_per_map emission shards for each of the global, caustic
// and volume photon counts (photons.photons_per_shard), whether or not the scene gets that map:
// a rule about the settings alone, so that the worker, which does not plan, checks it the
// same way.
func checkShards(s *pb.Scene) *FieldError {
	limit := rules.Scene.GetMaxShardsPerMap()
	for _, m := range []struct {
		name    string
		photons uint64
	}{{"global", GlobalPhotons(s)}, {"caustic", CausticPhotons(s)}, {"volume", VolumePhotons(s)}} {
		if n := ShardsPerMap(s, m.photons); n > limit {
			return rules.Errorf("photons.photons_per_shard", "%d photons per shard (photons.photons_per_shard) make %d emission shards of the %s map's %d photons (photons.%s_photons) per round, more than max_shards_per_map, %d: use more photons per shard",
				PhotonsPerShard(s), n, m.name, m.photons, m.name, limit)
		}
	}
	return nil
}

func ceilDiv(a, b uint64) uint64 { return (a + b - 1) / b }
