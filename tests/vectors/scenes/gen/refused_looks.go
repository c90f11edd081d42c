package main

import (
	"slices"

	pb "photonfarm/proto/renderfarm/v1"
)

// refusedLooks are the refusals of how a scene looks: the principled material, spot
// lights, the sun's disc, the environment, the thin lens and the output.
var refusedLooks = slices.Concat([]vectorCase{
	// Principled.
	refuse("refuse-base-color-below-0", "materials[6].principled.base_color.g", "Principled.base_color:gte", func(s *pb.Scene) { principled(s).BaseColor.G = -0.1 }),
	refuse("refuse-base-color-above-1", "materials[6].principled.base_color.b", "Principled.base_color:lte", func(s *pb.Scene) { principled(s).BaseColor.B = 1.1 }),
	refuse("refuse-metallic-below-0", "materials[6].principled.metallic", "Principled.metallic:gte", func(s *pb.Scene) { principled(s).Metallic = -0.5 }),
	refuse("refuse-metallic-above-1", "materials[6].principled.metallic", "Principled.metallic:lte", func(s *pb.Scene) { principled(s).Metallic = 1.5 }),
	refuse("refuse-roughness-below-0", "materials[6].principled.roughness", "Principled.roughness:gte", func(s *pb.Scene) { principled(s).Roughness = -0.5 }),
	refuse("refuse-roughness-above-1", "materials[6].principled.roughness", "Principled.roughness:lte", func(s *pb.Scene) { principled(s).Roughness = 1.01 }),
	refuse("refuse-normal-scale-below-0", "materials[6].principled.normal_scale", "Principled.normal_scale:gte", func(s *pb.Scene) { principled(s).NormalScale = -1 }),
	refuse("refuse-normal-scale-above-10", "materials[6].principled.normal_scale", "Principled.normal_scale:lte", func(s *pb.Scene) { principled(s).NormalScale = 10.5 }),
	refuse("refuse-principled-emission-below-0", "materials[6].principled.emission.r", "Principled.emission:gte", func(s *pb.Scene) { principled(s).Emission.R = -1 }),
	refuse("refuse-unknown-alpha-mode", "materials[6].principled.alpha_mode", "Principled.alpha_mode:enum", func(s *pb.Scene) { principled(s).AlphaMode = 5 }),
	refuse("refuse-transparency-below-0", "materials[6].principled.transparency", "Principled.transparency:gte", func(s *pb.Scene) { principled(s).Transparency = -0.1 }),
	refuse("refuse-transparency-above-1", "materials[6].principled.transparency", "Principled.transparency:lte", func(s *pb.Scene) { principled(s).Transparency = 1.1 }),
	refuse("refuse-alpha-cutoff-below-0", "materials[6].principled.alpha_cutoff", "Principled.alpha_cutoff:gte", func(s *pb.Scene) { principled(s).AlphaCutoff = -0.1 }),
	refuse("refuse-alpha-cutoff-above-1", "materials[6].principled.alpha_cutoff", "Principled.alpha_cutoff:lte", func(s *pb.Scene) { principled(s).AlphaCutoff = 2 }),

	// Spot lights.
	refuse("refuse-spot-light-without-position", "lights[2].spot.position", "SpotLight.position:required", func(s *pb.Scene) { spot(s).Position = nil }),
	refuse("refuse-spot-light-without-direction", "lights[2].spot.direction", "SpotLight.direction:required", func(s *pb.Scene) { spot(s).Direction = nil }),
	refuse("refuse-spot-direction-zero", "lights[2].spot.direction", "SpotLight.direction:note", func(s *pb.Scene) { spot(s).Direction = v(0, 0, 0) }),
	refuse("refuse-spot-light-without-intensity", "lights[2].spot.intensity", "SpotLight.intensity:required", func(s *pb.Scene) { spot(s).Intensity = nil }),
	refuse("refuse-spot-intensity-below-0", "lights[2].spot.intensity.b", "SpotLight.intensity:gte", func(s *pb.Scene) { spot(s).Intensity.B = -3 }),
	refuse("refuse-inner-cone-below-0", "lights[2].spot.inner_cone_degrees", "SpotLight.inner_cone_degrees:gte", func(s *pb.Scene) { spot(s).InnerConeDegrees = -1 }),
	refuse("refuse-inner-cone-above-90", "lights[2].spot.inner_cone_degrees", "SpotLight.inner_cone_degrees:lte", func(s *pb.Scene) { spot(s).InnerConeDegrees = 91 }),
	refuse("refuse-inner-cone-wider-than-the-outer-one", "lights[2].spot.inner_cone_degrees", "SpotLight.inner_cone_degrees:note", func(s *pb.Scene) {
		spot(s).InnerConeDegrees = 30.000001
	}),
	refuse("refuse-outer-cone-0", "lights[2].spot.outer_cone_degrees", "SpotLight.outer_cone_degrees:gt", func(s *pb.Scene) { spot(s).OuterConeDegrees = 0 }),
	refuse("refuse-outer-cone-above-90", "lights[2].spot.outer_cone_degrees", "SpotLight.outer_cone_degrees:lte", func(s *pb.Scene) { spot(s).OuterConeDegrees = 90.5 }),

	// The sun's disc, the environment, the lens and the output.
	refuse("refuse-sun-angular-diameter-below-0", "lights[1].sun.angular_diameter_degrees", "SunLight.angular_diameter_degrees:gte", func(s *pb.Scene) {
		sun(s).AngularDiameterDegrees = -0.5
	}),
	refuse("refuse-sun-angular-diameter-above-20", "lights[1].sun.angular_diameter_degrees", "SunLight.angular_diameter_degrees:lte", func(s *pb.Scene) {
		sun(s).AngularDiameterDegrees = 21
	}),
	refuse("refuse-environment-radiance-below-0", "environment.radiance.g", "Environment.radiance:gte", func(s *pb.Scene) { s.Environment.Radiance.G = -0.5 }),
	refuse("refuse-aperture-radius-below-0", "camera.aperture_radius", "Camera.aperture_radius:gte", func(s *pb.Scene) { s.Camera.ApertureRadius = -0.01 }),
	refuse("refuse-focus-distance-below-0", "camera.focus_distance", "Camera.focus_distance:gte", func(s *pb.Scene) { s.Camera.FocusDistance = -5 }),
	refuse("refuse-exposure-below-minus-20-stops", "output.exposure_stops", "Output.exposure_stops:gte", func(s *pb.Scene) { s.Output.ExposureStops = -20.5 }),
	refuse("refuse-exposure-above-20-stops", "output.exposure_stops", "Output.exposure_stops:lte", func(s *pb.Scene) { s.Output.ExposureStops = 21 }),
	refuse("refuse-unknown-tone-map", "output.tone_map", "Output.tone_map:enum", func(s *pb.Scene) { s.Output.ToneMap = 3 }),
},
	nonFinite("refuse-metallic", "materials[6].principled.metallic", "Principled.metallic", func(s *pb.Scene, x float64) { principled(s).Metallic = x }),
	nonFinite("refuse-roughness", "materials[6].principled.roughness", "Principled.roughness", func(s *pb.Scene, x float64) { principled(s).Roughness = x }),
	nonFinite("refuse-normal-scale", "materials[6].principled.normal_scale", "Principled.normal_scale", func(s *pb.Scene, x float64) { principled(s).NormalScale = x }),
	nonFinite("refuse-transparency", "materials[6].principled.transparency", "Principled.transparency", func(s *pb.Scene, x float64) { principled(s).Transparency = x }),
	nonFinite("refuse-alpha-cutoff", "materials[6].principled.alpha_cutoff", "Principled.alpha_cutoff", func(s *pb.Scene, x float64) { principled(s).AlphaCutoff = x }),
	nonFinite("refuse-inner-cone", "lights[2].spot.inner_cone_degrees", "SpotLight.inner_cone_degrees", func(s *pb.Scene, x float64) { spot(s).InnerConeDegrees = x }),
	nonFinite("refuse-outer-cone", "lights[2].spot.outer_cone_degrees", "SpotLight.outer_cone_degrees", func(s *pb.Scene, x float64) { spot(s).OuterConeDegrees = x }),
	nonFinite("refuse-sun-angular-diameter", "lights[1].sun.angular_diameter_degrees", "SunLight.angular_diameter_degrees", func(s *pb.Scene, x float64) {
		sun(s).AngularDiameterDegrees = x
	}),
	nonFinite("refuse-environment-rotation", "environment.rotation_degrees", "Environment.rotation_degrees", func(s *pb.Scene, x float64) { s.Environment.RotationDegrees = x }),
	nonFinite("refuse-aperture-radius", "camera.aperture_radius", "Camera.aperture_radius", func(s *pb.Scene, x float64) { s.Camera.ApertureRadius = x }),
	nonFinite("refuse-focus-distance", "camera.focus_distance", "Camera.focus_distance", func(s *pb.Scene, x float64) { s.Camera.FocusDistance = x }),
	nonFinite("refuse-exposure", "output.exposure_stops", "Output.exposure_stops", func(s *pb.Scene, x float64) { s.Output.ExposureStops = x }),
)
