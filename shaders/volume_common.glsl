// What every volume of a march has, whatever its kind: its origin (the eye relative to it), its
// empty-space grid (volume/OccupancyGrid.h) and its row of the transfer tables. Included once per
// volume with VOL_ replaced by that volume's prefix (engine/VolumeGL.h); VOL_INDEX is its index.

uniform vec3 VOL_eyeRel;            // eye - the volume's origin, ECEF (m), subtracted in double
uniform mat3 VOL_ecefToLocal;       // rows: the grid frame's axes (east, north, up at the origin)
uniform sampler3D VOL_grid;         // R16F, cells.x x cells.y x (cells.z + blocks.z): per cell the largest value a sample
                                    // there can see (z < cells.z), then per block of GRID_BLOCK^3 cells (z >= cells.z)
uniform vec3 VOL_gridMinLocal;      // the grid box's lower corner (m, local frame)
uniform vec3 VOL_gridCellSize;      // (m)
uniform ivec3 VOL_gridCells;
uniform vec2 VOL_tfRange;           // values of the transfer table's first and last entry edges
uniform float VOL_isoValue;
uniform vec3 VOL_isoColor;         // classify(isoValue).rgb, exact (CPU): the table quantises values
uniform float VOL_opacityZeroValue;
uniform float VOL_mipVisibleMin;    // MIP: a maximum below this is transparent
uniform float VOL_samplesPerCell;   // the step rule's samples per cell crossed (volume/StepRule.h); 0: fixed step

vec4 VOL_classify(float v) {
  float x = (v - VOL_tfRange.x) / (VOL_tfRange.y - VOL_tfRange.x);
  int i = clamp(int(x * float(TRANSFER_ENTRIES)), 0, TRANSFER_ENTRIES - 1);
  return texelFetch(u_transfer, ivec2(i, VOL_INDEX), 0);
}

// Pre-integrated classification (volume::transferIntegralTable): the cumulative integrals (of
// extinction * colour, of extinction) at a value, interpolated linearly between bin edges.
vec4 VOL_tfIntegral(float v) {
  float x = (v - VOL_tfRange.x) / (VOL_tfRange.y - VOL_tfRange.x) * float(TRANSFER_ENTRIES);
  return textureLod(u_tfIntegral, vec2((x + 0.5) / float(TRANSFER_ENTRIES + 1), (float(VOL_INDEX) + 0.5) / float(MAX_VOLUMES)), 0.0);
}

// The ray's parameter interval inside the grid box (empty: x > y); oL, dL in the local frame.
vec2 VOL_gridBoxInterval(vec3 oL, vec3 dL) {
  vec3 lo = VOL_gridMinLocal, hi = VOL_gridMinLocal + vec3(VOL_gridCells) * VOL_gridCellSize;
  vec3 inv = 1.0 / dL;
  vec3 t0 = (lo - oL) * inv, t1 = (hi - oL) * inv;
  float tNear = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z));
  float tFar = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
  return vec2(tNear, tFar);
}

// Empty-space skipping at ray parameter ts: ts itself when the cell there may hold a value at or
// above `threshold`, else where the ray leaves the empty cell (or its whole block when the block
// is below the threshold too); outside the box, where the ray next enters it (`box`, 1e30 when
// never). The ray in the grid's cell units, made once per ray by the caller: oC = (oL - the grid's
// lower corner) / cell size, dC = dL / cell size, iC = 1 / dC (no division per sample).
float VOL_emptyUntil(vec3 oC, vec3 dC, vec3 iC, vec2 box, float ts, float threshold) {
  ivec3 cell = ivec3(floor(oC + ts * dC));
  bool outside = any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, VOL_gridCells));
  if (outside) return box.x > box.y || box.y < ts ? 1e30 : max(box.x, ts);
  if (texelFetch(VOL_grid, cell, 0).r >= threshold) return ts;
  ivec3 block = cell / GRID_BLOCK;
  bool blockEmpty = texelFetch(VOL_grid, ivec3(block.xy, VOL_gridCells.z + block.z), 0).r < threshold;
  // Where the ray leaves the empty block or cell.
  vec3 lo = vec3(blockEmpty ? block * GRID_BLOCK : cell) - oC;
  vec3 t0 = lo * iC, t1 = (lo + (blockEmpty ? float(GRID_BLOCK) : 1.0)) * iC;
  vec3 tFar = max(t0, t1);
  float tOut = min(tFar.x, min(tFar.y, tFar.z));
  return tOut > ts ? tOut : ts;  // degenerate slab (NaN): no jump
}
