// The ray marcher of every volume kind (spec: volume/ReferenceRenderer.h, the double-precision
// rule it follows; docs/volume-rendering.md). One pass marches up to MAX_VOLUMES volumes
// together: where they overlap, extinctions add and colours are weighted by extinction.
//
// The program is assembled by engine/VolumeRendererGL (VolumeMarchProgram): "#define" lines
// (the variant, the injected constants of engine/VolumeGL.h), shared helpers (below, before
// main), then for each volume k volume_common.glsl and its kind's sample_KIND.glsl with VOL_
// replaced by "vK_", then the generated dispatch functions vol*(int k, ...) that this file calls.
// Loops over k run to the constant VOLUME_COUNT, so the compiler unrolls them and the dispatch
// folds away: a one-volume program is the one-volume marcher.
//
// Samples sit at t_i = (i + 0.5) * step from the eye (the same positions as the CPU reference);
// with a volume's samplesPerCell > 0 only the t_i the step rule picks (volume/StepRule.h: each sample has
// a level L from the cells there and stands for 2^L steps); volume k is sampled only at the t_i
// inside its interval (its kind's ray interval, before the
// globe's depth, and inside its empty-space grid's box when skipping), so a pixel pays only for
// the volumes its ray crosses.
//
// Variant constants: MARCH_MODE (0 DVR, 1 MIP, 2 isosurface, 3 debug: volume 0's coordinates at
// u_debugT), MARCH_COUNT (1: the same march, but the output is the samples taken: one per volume
// per position sampled, in .r), MARCH_SKIP_EMPTY (1: jump over grid cells that cannot contribute),
// MARCH_PREINTEGRATED (DVR: 0 each sample classified alone; 1 neighbouring samples of a volume
// as a linear segment, u_tfIntegral), MARCH_STEP_RULE (1: some volume follows the step rule; 0:
// every level is 0 at compile time, the fixed-step march), MARCH_ADAPTIVE (1: the refinement
// pass of adaptive refinement, below), MARCH_COLUMNS (1: the far field's columns, below),
// VOLUME_COUNT.

in vec2 v_uv;

uniform sampler2D u_transfer;    // RGBA32F, TRANSFER_ENTRIES x MAX_VOLUMES: row k = volume k's classify() over its tfRange;
                                 // DVR: alpha per step, pre-integrated DVR: (rgb, extinction per metre)
uniform sampler2D u_tfIntegral;  // RGBA32F, (TRANSFER_ENTRIES + 1) x MAX_VOLUMES, linear: volume::transferIntegralTable
uniform sampler2D u_globeDepth;  // reverse-Z depth of the globe pass (full resolution)
uniform mat3 u_cameraToEcef;
uniform float u_focalPx;         // of the full-resolution image
uniform vec2 u_imageSizePx;      // full resolution
uniform float u_near;
uniform float u_step;
uniform float u_earlyTermination;
uniform float u_debugT;
// Adaptive refinement (MARCH_ADAPTIVE; docs/volume-rendering.md, "Adaptive refinement"): the same
// march at u_coarseSizePx (premultiplied, the volume image of a pass at an image scale < 1).
uniform sampler2D u_coarse;
uniform vec2 u_coarseSizePx;
uniform float u_refineThreshold;  // in units of 1 (255 8-bit steps)

// The far field's columns (MARCH_COLUMNS; engine/FarFieldGL.h, docs/networks.md "The far
// field"): pixel (i, j) is the column at longitude u_columnBox.x + (i + 0.5) u_columnBox.z and
// latitude u_columnBox.y + (j + 0.5) u_columnBox.w (deg), marched down the ellipsoid's normal from
// height u_columnHeights.x to u_columnHeights.y (m). The "eye" of the volumes' uniforms is
// u_columnAnchor (ECEF relative to the Earth's centre, float: only the difference to the column's
// top point is used, which stays metres-accurate); the column's top is g_rayOffset from it.
uniform vec4 u_columnBox;
uniform vec2 u_columnHeights;
uniform vec3 u_columnAnchor;
vec3 g_rayOffset = vec3(0.0);

layout(location = 0) out vec4 o_color;

const int kColumns = MARCH_COLUMNS;
const int kMode = MARCH_MODE;
const int kSkipEmpty = MARCH_SKIP_EMPTY;
const int kPreintegrated = MARCH_PREINTEGRATED;
const int kStepRule = MARCH_STEP_RULE;
const int kAdaptive = MARCH_ADAPTIVE;
const int kCount = MARCH_COUNT;
float g_samplesTaken = 0.0;  // MARCH_COUNT

vec2 sphereInterval(vec3 o, vec3 d, float radius) {
  float b = dot(o, d);
  float c = dot(o, o) - radius * radius;
  float disc = b * b - c;
  if (disc < 0.0) return vec2(1.0, 0.0);
  float sq = sqrt(disc);
  return vec2(-b - sq, -b + sq);
}

void orderPair(inout float a, inout float b) {
  float lo = min(a, b);
  b = max(a, b);
  a = lo;
}

// The per-volume code and the dispatch functions are inserted at the next line.
// @VOLUMES@

// The step rule (volume/StepRule.h): the level of fine index c, the smallest of the volumes'
// whose range holds it (none: 0; a volume without the rule: 0) and of the pixel footprint's, and
// c rounded up to a multiple of 2^level.
int stepLevelAt(int c, vec3 dir, ivec2 range[VOLUME_COUNT]) {
  if (kStepRule == 0) return 0;
  // In steps: a pixel's footprint at t_c, t_c / focal / step = (c + 0.5) / focal (of the
  // full-resolution image: the positions' pattern stays below a pixel on the screen) ...
  float q = (float(c) + 0.5) / u_focalPx;
  float t = (float(c) + 0.5) * u_step;
  bool any = false;
  for (int k = 0; k < VOLUME_COUNT; ++k) {
    if (c >= range[k].x && c <= range[k].y) {
      // ... and the spacing each volume asks for: its cell crossing / samples per cell.
      float n = volSamplesPerCell(k);
      q = min(q, n > 0.0 ? volCellCrossing(k, volEyeRel(k) + t * dir, dir) / (n * u_step) : 0.0);
      any = true;
    }
  }
  // floor(log2(q)) = the highest set bit of floor(q), for q >= 1.
  return any && q >= 2.0 ? min(findMSB(int(min(q, 1e6))), MAX_STEP_LEVEL) : 0;
}

int alignUp(int c, int level) {
  int m = (1 << level) - 1;
  return (c + m) & ~m;
}

// A piece of path as (emission, optical depth): its premultiplied colour is emission * alpha /
// tau with alpha = 1 - exp(-tau) (emission when tau is tiny). Pieces of several volumes at the
// same place add (Max 1995, "Optical models for direct volume rendering").
vec4 pieceColor(vec4 piece) {
  float alpha = 1.0 - exp(-piece.a);
  return vec4(piece.a > 1e-9 ? piece.rgb * (alpha / piece.a) : piece.rgb, alpha);
}

// A path of `lengthMeters` with constant classification c = (rgb, extinction per metre).
vec4 constantPiece(vec4 c, float lengthMeters) {
  float tau = c.a * lengthMeters;
  return vec4(c.rgb * tau, tau);
}

// A path of `len` metres along which the value goes linearly from v0 (front) to v1 (back): exact optical depth
// from the integral table; emission from the integral of extinction * colour. Below a change of
// 1e-4 of the table's value range (0.013 dBZ for reflectivity) the table's difference quotient
// loses float precision (its integrals carry a relative error of ~1e-7 of the whole range), and
// the path is taken as the mean of its ends' classifications.
vec4 linearPiece(float v0, vec4 i0, vec4 c0, float v1, vec4 i1, vec4 c1, vec2 tfRange, float len) {
  float dv = v1 - v0;
  if (abs(dv) > 1e-4 * (tfRange.y - tfRange.x))
    return vec4(len * (i1.rgb - i0.rgb) / dv, max(len * (i1.a - i0.a) / dv, 0.0));
  return vec4(len * 0.5 * (c0.rgb * c0.a + c1.rgb * c1.a), max(len * 0.5 * (c0.a + c1.a), 0.0));
}

void composite(inout vec4 acc, vec4 premultiplied) {
  acc.rgb += (1.0 - acc.a) * premultiplied.rgb;
  acc.a += (1.0 - acc.a) * premultiplied.a;
}

void main() {
  vec2 pixel = vec2(v_uv.x * u_imageSizePx.x, (1.0 - v_uv.y) * u_imageSizePx.y);  // from the top
  vec3 dirEye = vec3((pixel.x - 0.5 * u_imageSizePx.x) / u_focalPx, (0.5 * u_imageSizePx.y - pixel.y) / u_focalPx, -1.0);
  vec3 dir = normalize(u_cameraToEcef * dirEye);
  if (kColumns == 1) {
    vec2 lonLat = radians(u_columnBox.xy + gl_FragCoord.xy * u_columnBox.zw);
    float cl = cos(lonLat.y), sl = sin(lonLat.y), co = cos(lonLat.x), so = sin(lonLat.x);
    float n = WGS84_A / sqrt(1.0 - WGS84_E2 * sl * sl);
    float h = u_columnHeights.x;
    g_rayOffset = vec3((n + h) * cl * co, (n + h) * cl * so, (n * (1.0 - WGS84_E2) + h) * sl) - u_columnAnchor;
    dir = -vec3(cl * co, cl * so, sl);
  }

  if (kMode == 3) {
    o_color = vec4(volDebug(0, volEyeRel(0) + u_debugT * dir), 1.0);
    return;
  }

  // The globe hides what is behind it: reverse-Z depth = near / view distance.
  float depth = kColumns == 1 ? 0.0 : textureLod(u_globeDepth, v_uv, 0.0).r;

  if (kAdaptive == 1) {
    // The four small-image pixels around this one (their centres at (j + 0.5) / size, the
    // bilinear lookup of the composite pass); where they agree within the threshold in every
    // channel and the globe covers all or none of them and of this pixel, their bilinear
    // value; else this pixel is marched below.
    vec2 cp = v_uv * u_coarseSizePx - 0.5;
    ivec2 j0 = ivec2(floor(cp));
    vec2 f = cp - vec2(j0);
    ivec2 hiJ = ivec2(u_coarseSizePx) - 1;
    ivec2 a0 = clamp(j0, ivec2(0), hiJ), a1 = clamp(j0 + 1, ivec2(0), hiJ);
    vec4 c00 = texelFetch(u_coarse, a0, 0), c10 = texelFetch(u_coarse, ivec2(a1.x, a0.y), 0);
    vec4 c01 = texelFetch(u_coarse, ivec2(a0.x, a1.y), 0), c11 = texelFetch(u_coarse, a1, 0);
    vec4 spread = max(max(c00, c10), max(c01, c11)) - min(min(c00, c10), min(c01, c11));
    float ground = 0.0;
    ground += textureLod(u_globeDepth, (vec2(a0) + 0.5) / u_coarseSizePx, 0.0).r > 0.0 ? 1.0 : 0.0;
    ground += textureLod(u_globeDepth, (vec2(a1.x, a0.y) + 0.5) / u_coarseSizePx, 0.0).r > 0.0 ? 1.0 : 0.0;
    ground += textureLod(u_globeDepth, (vec2(a0.x, a1.y) + 0.5) / u_coarseSizePx, 0.0).r > 0.0 ? 1.0 : 0.0;
    ground += textureLod(u_globeDepth, (vec2(a1) + 0.5) / u_coarseSizePx, 0.0).r > 0.0 ? 1.0 : 0.0;
    bool sameCover = depth > 0.0 ? ground == 4.0 : ground == 0.0;
    if (sameCover && max(max(spread.r, spread.g), max(spread.b, spread.a)) <= u_refineThreshold) {
      o_color = mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
      return;
    }
  }
  float tGround = depth > 0.0 ? (u_near / depth) / (-dirEye.z / length(dirEye)) : 1e30;
  if (kColumns == 1) tGround = u_columnHeights.x - u_columnHeights.y;  // the column's bottom
  o_color = vec4(0.0);

  // Each volume's sample indices [first, last] and, for skipping, its ray in its grid's cell units.
  ivec2 range[VOLUME_COUNT];
  vec3 oC[VOLUME_COUNT], dC[VOLUME_COUNT], iC[VOLUME_COUNT];  // the ray in the grid's cell units, 1 / dC
  vec2 box[VOLUME_COUNT];
  float a = 1e30, b = -1e30;
  for (int k = 0; k < VOLUME_COUNT; ++k) {
    vec2 s = volInterval(k, dir, tGround);
    vec3 oL = volEcefToLocal(k) * volEyeRel(k);
    vec3 dL = volEcefToLocal(k) * dir;
    oC[k] = (oL - volGridMinLocal(k)) / volGridCellSize(k);
    dC[k] = dL / volGridCellSize(k);
    iC[k] = 1.0 / dC[k];
    // Outside the grid's box every sample is empty (the box holds every measured value's
    // support): with skipping on, march only across the box.
    box[k] = kSkipEmpty == 1 ? volGridBox(k, oL, dL) : vec2(-1e30, 1e30);
    s.x = max(s.x, box[k].x);
    s.y = min(s.y, box[k].y);
    range[k] = s.x <= s.y ? ivec2(int(ceil(s.x / u_step - 0.5)), int(floor(s.y / u_step - 0.5))) : ivec2(1, 0);
    if (range[k].x <= range[k].y) {
      a = min(a, s.x);
      b = max(b, s.y);
    }
  }
  if (a > b) return;

  vec4 acc = vec4(0.0);
  // Pre-integrated DVR, per volume: the last sample taken (index, echo, value, integrals,
  // classification). A run of echo samples i..j stands for the path from t_i - step/2 to
  // t_j + step/2, like the post-classified samples it replaces: half a step of constant
  // classification at each end, a linear segment between neighbours.
  int prevIndex[VOLUME_COUNT];
  float prevHalfStep[VOLUME_COUNT];  // half the step of the last sample taken
  bool prevEcho[VOLUME_COUNT];
  float prevV[VOLUME_COUNT];
  vec4 prevIntegral[VOLUME_COUNT], prevC[VOLUME_COUNT];
  float maxValue[VOLUME_COUNT], tOfMax[VOLUME_COUNT];
  for (int k = 0; k < VOLUME_COUNT; ++k) {
    prevIndex[k] = -2;
    prevHalfStep[k] = 0.5 * u_step;
    prevEcho[k] = false;
    prevV[k] = 0.0;
    prevIntegral[k] = vec4(0.0);
    prevC[k] = vec4(0.0);
    maxValue[k] = -1e30;
    tOfMax[k] = 0.0;
  }
  bool hit = false;
  float hitT = 0.0;
  int hitK = 0;
  int i = int(ceil(a / u_step - 0.5));
  int iEnd = int(floor(b / u_step - 0.5));
  int level = stepLevelAt(i, dir, range);
  i = alignUp(i, level);
  int lastIndex = -2;  // the march's previous sample (-2 after a jump over empty space)
  while (i <= iEnd) {
    if (kSkipEmpty == 1) {
      // While nothing at the sample can change the result in any volume (DVR: nothing above its
      // zero-opacity value; MIP: nothing above its maximum so far or its first visible colour;
      // isosurface: nothing at or above its iso value), jump to the first sample after the
      // nearest place where that may change, staying on the t_i grid. An inner loop, so that on
      // SIMD hardware the lanes of a group skip together and then sample together.
      bool jumped = false;
      while (i <= iEnd) {
        float ts = (float(i) + 0.5) * u_step;
        float tNext = 1e30;
        bool empty = true;
        for (int k = 0; k < VOLUME_COUNT; ++k) {
          if (i < range[k].x) {
            tNext = min(tNext, (float(range[k].x) + 0.5) * u_step);  // the volume starts later
          } else if (i <= range[k].y) {
            float threshold = kMode == 0 ? volOpacityZero(k) : (kMode == 1 ? max(maxValue[k], volMipVisibleMin(k)) : volIso(k));
            float e = volEmptyUntil(k, oC[k], dC[k], iC[k], box[k], ts, threshold);
            if (e <= ts) empty = false;
            tNext = min(tNext, e);
          }
        }
        if (!empty) break;
        // Aligned by the last level while jumping; the level of where the jumps end is found
        // once, after them (the same place wherever the level is the same on both sides).
        i = alignUp(max(i + 1, int(ceil(min(tNext, b) / u_step - 0.5))), level);
        jumped = true;
      }
      if (jumped) {
        level = stepLevelAt(i, dir, range);
        i = alignUp(i, level);
        lastIndex = -2;
      }
      if (i > iEnd) break;
    }
    float t = (float(i) + 0.5) * u_step;
    float stepHere = u_step * float(1 << level);  // what this sample stands for
    // This sample in every volume whose range holds it.
    vec4 tails = vec4(0.0), pieces = vec4(0.0);  // pre-integrated: run ends, then this sample's pieces
    int contributing = 0;
    vec4 single = vec4(0.0);
    float transmitted = 1.0, extinction = 0.0;
    vec3 weightedRgb = vec3(0.0);
    // No `continue` in this loop: Mesa does not unroll a loop that holds one, and on llvmpipe the
    // loop left in place (lane masks around the whole sampler) made the default one-radar DVR
    // frame 1.6x slower (docs/bench-volume.md, "The march loop and llvmpipe").
    for (int k = 0; k < VOLUME_COUNT; ++k) {
      bool inRange = i >= range[k].x && i <= range[k].y;
      float v = 0.0;
      int state = inRange ? volSample(k, volEyeRel(k) + t * dir, v) : STATE_NOT_ECHO;
      if (kCount == 1 && inRange) g_samplesTaken += 1.0;
      if (kMode == 0 && kPreintegrated == 1 && inRange) {
        // A run is made of echo samples above the zero-opacity value: the samples the empty-space
        // grid may skip are all at or below it, so the runs, and the picture, do not depend on
        // whether skipping is on.
        bool echo = state == STATE_ECHO && v > volOpacityZero(k);
        vec4 c = volClassify(k, v);
        vec4 integral = volTfIntegral(k, v);
        bool adjacent = prevEcho[k] && echo && prevIndex[k] == lastIndex;
        // A run ends (this sample is not echo, or empty cells were skipped since the last one):
        // the last sample's half step.
        if (prevEcho[k] && !adjacent) tails += constantPiece(prevC[k], prevHalfStep[k]);
        if (echo)
          pieces += adjacent ? linearPiece(prevV[k], prevIntegral[k], prevC[k], v, integral, c, volTfRange(k),
                                           float(i - prevIndex[k]) * u_step)
                             : constantPiece(c, 0.5 * stepHere);
        prevIndex[k] = i;
        prevHalfStep[k] = 0.5 * stepHere;
        prevEcho[k] = echo;
        prevV[k] = v;
        prevIntegral[k] = integral;
        prevC[k] = c;
      } else if (kMode == 0 && kPreintegrated == 0 && state == STATE_ECHO) {
        vec4 c = volClassify(k, v);  // alpha corrected for the step length on the CPU
        // A sample of level L stands for 2^L steps: 1 - (1 - alpha)^(2^L), by L squarings.
        float kept = 1.0 - c.a;
        for (int j = 0; j < level; ++j) kept *= kept;
        c.a = 1.0 - kept;
        if (c.a > 0.0) {
          ++contributing;
          single = c;
          if (VOLUME_COUNT > 1) {
            transmitted *= 1.0 - c.a;
            // Extinction x step of this volume: -ln(1 - alpha_step); the common factor cancels in the weights.
            float x = -log(max(1.0 - c.a, 1e-7));
            extinction += x;
            weightedRgb += x * c.rgb;
          }
        }
      } else if (kMode == 1) {
        if (state == STATE_ECHO && v > maxValue[k]) {
          maxValue[k] = v;
          tOfMax[k] = t;
        }
      } else if (kMode == 2) {
        if (!hit && state == STATE_ECHO && v >= volIso(k)) {
          hit = true;
          hitK = k;
        }
      }
    }
    if (kMode == 0 && kPreintegrated == 1) {
      if (tails.a > 0.0 || any(greaterThan(tails.rgb, vec3(0.0)))) composite(acc, pieceColor(tails));
      if (pieces.a > 0.0 || any(greaterThan(pieces.rgb, vec3(0.0)))) composite(acc, pieceColor(pieces));
      if (acc.a >= u_earlyTermination) break;
    } else if (kMode == 0) {
      if (contributing > 0) {
        // One volume: its own colour and opacity; several: extinctions add (opacity 1 - prod(1 -
        // a_k)), colour weighted by extinction.
        vec4 c = VOLUME_COUNT == 1 || contributing == 1 ? vec4(single.a * single.rgb, single.a)
                                   : vec4((1.0 - transmitted) * weightedRgb / max(extinction, 1e-30), 1.0 - transmitted);
        composite(acc, c);
        if (acc.a >= u_earlyTermination) break;
      }
    } else if (kMode == 2 && hit) {
      // Bisection between the previous sample position and this one, in the volume hit.
      float lo = t - stepHere, hi = t;
      for (int it = 0; it < 8; ++it) {
        float mid = 0.5 * (lo + hi);
        float vm;
        int sm = volSample(hitK, volEyeRel(hitK) + mid * dir, vm);
        if (kCount == 1) g_samplesTaken += 1.0;
        if (sm == STATE_ECHO && vm >= volIso(hitK)) hi = mid; else lo = mid;
      }
      hitT = hi;
      break;
    }
    lastIndex = i;
    int c = i + (1 << level);
    level = stepLevelAt(c, dir, range);
    i = alignUp(c, level);
  }

  if (kMode == 0) {
    if (kPreintegrated == 1 && acc.a < u_earlyTermination) {
      vec4 tails = vec4(0.0);
      for (int k = 0; k < VOLUME_COUNT; ++k)
        if (prevEcho[k]) tails += constantPiece(prevC[k], prevHalfStep[k]);
      if (tails.a > 0.0) composite(acc, pieceColor(tails));
    }
    o_color = acc;
  } else if (kMode == 1) {
    // Each volume's maximum, composited front to back in the order of where it was reached.
    bool used[VOLUME_COUNT];
    for (int k = 0; k < VOLUME_COUNT; ++k) used[k] = false;
    vec4 outColor = vec4(0.0);
    for (int n = 0; n < VOLUME_COUNT; ++n) {
      int best = -1;
      for (int k = 0; k < VOLUME_COUNT; ++k)
        if (!used[k] && maxValue[k] > -1e29 && (best < 0 || tOfMax[k] < tOfMax[best])) best = k;
      if (best < 0) break;
      used[best] = true;
      vec4 c = volClassify(best, maxValue[best]);
      composite(outColor, vec4(c.rgb * c.a, c.a));
    }
    o_color = outColor;
  } else if (kMode == 2 && hit) {
    vec3 p = volEyeRel(hitK) + hitT * dir;
    float h = 0.5 * u_step * float(1 << level);
    vec3 grad;
    for (int axis = 0; axis < 3; ++axis) {
      vec3 e = vec3(0.0);
      e[axis] = h;
      float vp, vm;
      int sp = volSample(hitK, p + e, vp);
      int sm = volSample(hitK, p - e, vm);
      if (kCount == 1) g_samplesTaken += 2.0;
      if (sp != STATE_ECHO) vp = volOpacityZero(hitK);
      if (sm != STATE_ECHO) vm = volOpacityZero(hitK);
      grad[axis] = (vp - vm) / (2.0 * h);
    }
    vec3 n = length(grad) > 0.0 ? -normalize(grad) : -dir;
    o_color = vec4(volIsoColor(hitK) * (0.3 + 0.7 * abs(dot(n, dir))), 1.0);
  }
  if (kCount == 1) o_color = vec4(g_samplesTaken, 0.0, 0.0, 1.0);
}
