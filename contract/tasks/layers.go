package tasks

// MeasuredLayers are the light layers of a render whose RMSE against a reference a
// composite reports apart from the beauty's (RoundMetrics.layer_reference_rmse), in the
// order reports show them. The worker's list is worker/image/reference_exr.h
// kMeasuredLayers; TestMeasuredLayersMatchTheWorkers keeps the two equal.
var MeasuredLayers = []string{"direct", "indirect", "caustic", "volume"}
