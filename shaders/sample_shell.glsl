// Sampler of the analytic uniform shell (spec: volume/AnalyticVolume.h), included once per shell
// of a march with VOL_ replaced by that volume's prefix (engine/VolumeGL.h). Positions are
// float32 relative to the shell's centre (subtracted in double on the CPU).

uniform vec3 VOL_shellRadii;  // inner, outer radius (m), value

vec3 VOL_debugCoordinates(vec3 p) { return vec3(length(p), 0.0, 0.0); }

// The step rule (volume/StepRule.h): this kind has no cell crossing yet, its samples take the
// fixed step.
float VOL_cellCrossing(vec3 p, vec3 dir) { return 0.0; }

int VOL_sample(vec3 p, out float value) {
  float r = length(p);
  value = VOL_shellRadii.z;
  return r >= VOL_shellRadii.x && r <= VOL_shellRadii.y ? STATE_ECHO : STATE_NOT_ECHO;
}

vec2 VOL_interval(vec3 eyeRel, vec3 dir, float tMax) {
  vec2 span = sphereInterval(eyeRel, dir, VOL_shellRadii.y);
  return vec2(max(span.x, 0.0), min(span.y, tMax));
}
