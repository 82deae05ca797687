#pragma once
// A Kinect-like depth sensor model applied to an ideal (exact) depth image.
//
// Structured-light sensors measure disparity d = b f / z (b: projector-camera baseline in metres, f: focal
// length in pixels). The model adds zero-mean Gaussian noise of sigma_d pixels to d, quantises it to steps of
// disparityStepPx, and converts back, so the depth noise grows as sigma_z = z^2 / (b f) sigma_d. Pixels whose
// surface is seen at a grazing angle, that lie next to a depth discontinuity (the sensor's shadow/edge
// dropouts), or whose depth falls outside [minDepthM, maxDepthM] read 0 (no reading).
// Randomness is a pure function of (frame seed, pixel index): results do not depend on threads or order.

#include <cstdint>

#include "core/image.h"

namespace sb::synth {

struct SensorModel {
  double minDepthM = 0.4;  // metres; nearer readings are missing (always applied)
  double maxDepthM = 4.5;  // metres; farther readings are missing (always applied)

  bool noise = true;                 // false: exact depth (only the range limits apply)
  double baselineM = 0.075;          // projector-camera baseline, metres
  // std of the disparity noise, pixels. 0.05 px with the 1/8 px quantisation below gives sigma_z of about 0.7 cm
  // at 2 m and 1.5 cm at 3 m (ICL-NUIM's f = 481 px), the Kinect v1 axial noise measured by Nguyen, Izadi and
  // Lovell (3DIMPVT 2012: 0.0012 + 0.0019 (z - 0.4)^2 m, i.e. 0.6 cm at 2 m, 1.4 cm at 3 m). The former 0.2 px
  // was four times that (6.6 cm at 3.4 m): along the ICL-NUIM trajectories in the procedural living room, which
  // look across 3-4 m at the start, DEFAULT KinectFusion tracked none of the frames.
  double sigmaDisparityPx = 0.05;
  double disparityStepPx = 0.125;    // disparity quantisation step, pixels (0 = none)
  double maxIncidenceDeg = 75.0;     // readings missing where ray and surface normal differ by more, degrees
  double edgeJumpM = 0.05;           // a neighbour nearer/farther by more than edgeJumpM + edgeJumpRatio * z ...
  double edgeJumpRatio = 0.03;       // ... (metres, fraction of z) marks a depth discontinuity
  int edgeRadiusPx = 1;              // neighbourhood (pixels) searched for discontinuities

  // Analytic std of depth (metres) from the disparity noise alone at depth z for focal length fPx.
  double sigmaDepthM(double zM, double fPx) const { return zM * zM / (baselineM * fPx) * sigmaDisparityPx; }
};

// Exact depth along the optical axis (metres, 0 = nothing hit) and |cos| of the angle between the viewing
// ray and the surface normal, per pixel.
struct IdealFrame {
  Image<float> depthM;
  Image<float> cosIncidence;
};

// Seed of frame `frameIndex` of a sequence rendered with `baseSeed`.
uint64_t frameSeed(uint64_t baseSeed, uint64_t frameIndex);

// Applies the sensor model to rows [rowBegin, rowEnd) of `ideal`, writing metres (0 = no reading) to `out`
// (already sized). fPx is the focal length used for disparity (fx).
void applySensorModel(const IdealFrame& ideal, const SensorModel& model, double fPx, uint64_t seed,
                      int rowBegin, int rowEnd, DepthMeters& out);

// Converts metres to raw units (rounded; 0 stays 0; readings beyond the uint16 range become 0).
void toRaw(const DepthMeters& meters, double depthScale, DepthRaw& out);

}  // namespace sb::synth
