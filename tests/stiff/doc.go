// Package stiff is the stiff and extreme cases suite: tiny scenes at the edges of what the
// renderer must survive (scene scales from 1e-4 to 1e5, a pin-point light, glass of index
// 1.0001 and 4, grazing light, a scene far from the origin, a camera inside glass, 1 to
// 10 million photons, a near-zero search radius, degenerate triangles), a white furnace
// with an analytic answer, and participating media (sigma_t from 1e-6 to 1e4 per unit, g of
// +-0.999, albedo 0 and 1, the camera and a light inside fog, a medium inside glass) in
// furnaces with closed forms, each rendered on one real local farm (`farm coordinator` and
// two `farm-worker` processes from $FARM_BIN_DIR, started once for the whole suite). Every
// final EXR must be free of NaN and infinity, no camera sample of the job may have come out
// NaN or infinite (the coordinator's count), and every image must stay within the energy
// bounds each case states. See tests/README.md, "Stiff and extreme cases".
package stiff
