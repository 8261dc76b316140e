#include <atmoglobe/engine/GridSourceGL.h>

#include <atmoglobe/engine/Readout.h>
#include <atmoglobe/engine/SlicePlot.h>
#include <atmoglobe/engine/ViewCulling.h>
#include <atmoglobe/globe/Ellipsoid.h>
#include <atmoglobe/volume/Crop.h>
#include <atmoglobe/volume/Decimate.h>
#include <atmoglobe/volume/GridDetail.h>
#include <atmoglobe/volume/GridReader.h>
#include <atmoglobe/volume/SliceSource.h>
#include <atmoglobe/volume/StepCache.h>
#include <atmoglobe/volume/VerticalExaggeration.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace atmoglobe::engine {

namespace {

// The crop box's cut of a grid as read (the reader already kept only the box's columns and one
// more on each side; heights and the exact box are cut here).
Status cropGridLayer(const VolumeLayerDescription& d, volume::GridVolume& grid) {
  if (d.settings.crop.coversEveryLonLat() && d.settings.crop.coversEveryHeight()) return Ok{};
  auto geoid = cropGeoid(d.settings, d.useGeoid);
  if (!geoid) return makeError(d.path + ": crop heights: " + geoid.error());
  volume::cropGrid(grid, d.settings.crop, *geoid);
  if (!(grid.valueMin <= grid.valueMax))
    return makeError(d.path + ": the crop box leaves no value of " + grid.variable);
  return Ok{};
}

// What a grid layer reads: its variable, crop and datum (the time step is set by the caller).
volume::GridReadOptions gridReadOptions(const VolumeLayerDescription& d) {
  volume::GridReadOptions read;
  read.variable = d.field;
  read.useGeoid = d.useGeoid;
  read.member = d.member;
  read.ensemble = d.ensemble;
  read.extraIndex = d.gridIndex;
  read.crop.southDeg = d.settings.crop.southDeg;
  read.crop.northDeg = d.settings.crop.northDeg;
  read.crop.westDeg = d.settings.crop.westDeg;
  read.crop.eastDeg = d.settings.crop.eastDeg;
  return read;
}

// A grid layer's render options; colours over `range` (the values of the step first loaded).
Result<VolumeRenderOptions> gridRenderOptions(const VolumeLayerDescription& d, const volume::GridVolume& grid,
                                              const volume::ValueRange& range) {
  return layerRenderOptions(d, volume::FieldInfo{grid.variable, grid.units, grid.standardName},
                            std::numeric_limits<double>::quiet_NaN(), range);
}

// What a GPU volume costs the budget: its CPU twin, its empty-space grid on the CPU, its textures.
std::uint64_t budgetBytes(const GridVolumeGL& v) {
  const volume::OccupancyGrid& o = v.occupancy().grid();
  return volume::gridVolumeBytes(v.grid()) + (o.maxValues.capacity() + o.blockMaxValues.capacity()) * sizeof(float) +
         v.gpuBytes();
}

class GridStepPreparer final : public StepPreparer {
 public:
  GridStepPreparer(VolumeLayerDescription d, double exaggeration)
      : description_(std::move(d)), exaggeration_(exaggeration) {}
  std::optional<Prepared> prepare(std::size_t step, const PrepareContext&) const override {
    auto grid = prepareGridStep(description_, step, exaggeration_);
    if (!grid || !GridVolumeGL::checkDrawable(*grid)) return std::nullopt;
    auto prepared = GridVolumeGL::prepare(*grid);  // texels, lookup tables, empty-space grid
    const std::uint64_t bytes = prepared->bytes();
    return Prepared{std::move(prepared), bytes};
  }

 private:
  VolumeLayerDescription description_;
  double exaggeration_;
};

}  // namespace

Result<volume::GridVolume> prepareGridStep(const VolumeLayerDescription& d, std::size_t step, double exaggeration) {
  volume::GridReadOptions read = gridReadOptions(d);
  read.timeIndex = step;
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  if (auto st = cropGridLayer(d, *grid); !st) return st.forwardError();
  volume::exaggerateGrid(*grid, exaggeration);
  return grid;
}

Result<std::unique_ptr<GridSourceGL>> GridSourceGL::open(const VolumeLayerDescription& d, SourceContext context) {
  if (d.kind != VolumeKind::Grid) return makeError(d.path + ": a " + nameOf(d.kind) + " layer is not a grid");
  volume::GridReadOptions read = gridReadOptions(d);
  if (auto st = volume::selectGridTime(d.time, read); !st) return makeError(d.path + ": " + st.error());
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  if (auto st = cropGridLayer(d, *grid); !st) return st.forwardError();
  const volume::ValueRange range{grid->valueMin, grid->valueMax};
  if (!(range.minValue <= range.maxValue))
    return makeError(d.path + ": " + grid->variable + " has no valid value at " +
                     (grid->validTime.empty() ? std::string("the step read") : grid->validTime));
  auto o = gridRenderOptions(d, *grid, range);
  if (!o) return o.forwardError();
  volume::exaggerateGrid(*grid, context.exaggeration);
  auto gl = GridVolumeGL::create(*grid);
  if (!gl) return gl.forwardError();
  std::unique_ptr<GridSourceGL> source(new GridSourceGL());
  source->volume_ = std::move(*gl);
  source->options_ = std::move(*o);
  source->description_ = d;
  source->step_ = grid->timeIndex;
  source->synthetic_ = volume::fileSaysSynthetic(d.path);
  source->mosaicRule_ = volume::mosaicOverlapRule(d.path);
  source->firstRange_ = range;
  context.cache.put(stepKey(context.layer, source->step_, true), source->volume_, budgetBytes(*source->volume_));
  return source;
}

std::vector<std::string> GridSourceGL::fieldChoices() const {
  if (!variables_) {
    variables_.emplace();
    if (auto info = volume::describeGridFile(description_.path, volume_->grid().variable))
      for (const volume::GridVariableInfo& v : info->variables)
        if (v.onGrid) variables_->push_back(v.name);
  }
  return *variables_;
}

volume::ValueHistogram GridSourceGL::histogram(int bins) const { return volume::valueHistogram(volume_->grid(), bins); }

Result<std::vector<std::string>> GridSourceGL::times() const {
  auto info = volume::describeGridFile(description_.path, description_.field);
  if (!info) return info.forwardError();
  return info->times;
}

Result<std::shared_ptr<const GridVolumeGL::Prepared>> GridSourceGL::stepPrepared(std::size_t step,
                                                                                 SourceContext context) {
  const std::string cpuKey = stepKey(context.layer, step, false);
  context.cache.waitWhileLoading(cpuKey);  // a background loader's read in flight: wait, do not read twice
  if (auto cpu = context.cache.get<GridVolumeGL::Prepared>(cpuKey)) return cpu;
  auto grid = prepareGridStep(description_, step, context.exaggeration);
  if (!grid) return grid.forwardError();
  if (auto st = GridVolumeGL::checkDrawable(*grid); !st) return st.forwardError();
  auto prepared = GridVolumeGL::prepare(*grid);
  context.cache.put(cpuKey, prepared, prepared->bytes());
  return prepared;
}

Result<std::shared_ptr<const volume::GridVolume>> GridSourceGL::stepData(std::size_t step, SourceContext context) {
  if (auto gl = context.cache.get<GridVolumeGL>(stepKey(context.layer, step, true)))
    return std::shared_ptr<const volume::GridVolume>(gl, &gl->grid());
  auto prepared = stepPrepared(step, context);
  if (!prepared) return prepared.forwardError();
  return std::shared_ptr<const volume::GridVolume>(*prepared, (*prepared)->grid.get());
}

Status GridSourceGL::showStep(std::size_t step, double fraction, SourceContext context) {
  if (!(fraction >= 0.0 && fraction < 1.0)) return makeError(description_.path + ": time fraction outside [0, 1)");
  if (step_ == step && stepFraction_ == fraction) return Ok{};
  volume::StepCache& cache = context.cache;
  cache.releaseDropped();  // GPU volumes dropped by a worker's put die here, on the GL thread
  const std::string key = stepKey(context.layer, step, true, fraction);
  if (auto cached = cache.get<GridVolumeGL>(key)) {
    volume_ = std::const_pointer_cast<GridVolumeGL>(cached);
  } else {
    Result<std::unique_ptr<GridVolumeGL>> gl = makeError("");
    if (fraction == 0.0) {
      // Prepared ahead by a ScenePrefetcher (only the upload is left), else read and prepared now.
      auto prepared = stepPrepared(step, context);
      if (!prepared) return prepared.forwardError();
      gl = GridVolumeGL::create(std::move(*prepared));
    } else {
      auto grid = stepData(step, context);
      if (!grid) return grid.forwardError();
      auto next = stepData(step + 1, context);
      if (!next) return next.forwardError();
      auto blended = volume::interpolateGridSteps(**grid, **next, fraction);
      if (!blended) return blended.forwardError();
      gl = GridVolumeGL::create(*blended);
    }
    if (!gl) return gl.forwardError();
    volume_ = std::move(*gl);
    // A whole step's CPU data now live in its GPU volume's twin (interpolation keeps both ends).
    if (fraction == 0.0) cache.erase(stepKey(context.layer, step, false));
    cache.put(key, volume_, budgetBytes(*volume_));
  }
  step_ = step;
  stepFraction_ = fraction;
  cache.releaseDropped();
  return Ok{};
}

std::unique_ptr<StepPreparer> GridSourceGL::preparer(double exaggeration) const {
  return std::make_unique<GridStepPreparer>(description_, exaggeration);
}

Status GridSourceGL::reload(const VolumeLayerDescription& d, std::size_t step, double fraction, SourceContext context) {
  volume::GridReadOptions read = gridReadOptions(d);
  read.timeIndex = step;
  auto grid = volume::readGridVolume(d.path, read);
  if (!grid) return grid.forwardError();
  if (auto st = cropGridLayer(d, *grid); !st) return st.forwardError();
  if (fraction > 0.0) {
    read.timeIndex = step + 1;
    auto next = volume::readGridVolume(d.path, read);
    if (!next) return next.forwardError();
    if (auto st = cropGridLayer(d, *next); !st) return st.forwardError();
    auto blended = volume::interpolateGridSteps(*grid, *next, fraction);
    if (!blended) return blended.forwardError();
    grid = std::move(blended);
  }
  volume::exaggerateGrid(*grid, context.exaggeration);
  auto gl = GridVolumeGL::create(*grid);
  if (!gl) return gl.forwardError();
  context.cache.erasePrefix(stepKeyPrefix(context.layer));
  volume_ = std::move(*gl);
  step_ = step;
  stepFraction_ = fraction;
  context.cache.put(stepKey(context.layer, step, true, fraction), volume_, budgetBytes(*volume_));
  context.cache.releaseDropped();
  return Ok{};
}

Status GridSourceGL::setDescription(const VolumeLayerDescription& d, SourceContext context) {
  switch (layerChange(description_, d)) {
    case LayerChange::None: return Ok{};
    case LayerChange::Reload: {
      const volume::ValueRange previousRange = firstRange_;
      if (d.field != description_.field || d.path != description_.path) firstRange_ = {};  // new colours' range
      if (auto st = reload(d, step_, stepFraction_, context); !st) {
        firstRange_ = previousRange;
        return st;
      }
      if (d.path != description_.path) variables_.reset();
      if (!(firstRange_.minValue < firstRange_.maxValue)) {
        const volume::GridVolume& g = volume_->grid();
        firstRange_ = {g.valueMin, g.valueMax};
      }
      break;
    }
    case LayerChange::Options: break;
  }
  auto o = gridRenderOptions(d, volume_->grid(), firstRange_);
  if (!o) return o.forwardError();
  options_ = std::move(*o);
  description_ = d;
  return Ok{};
}

Status GridSourceGL::applyExaggeration(SourceContext context) {
  return reload(description_, step_, stepFraction_, context);
}

namespace {

// 1 for a volume uploaded at the resolution it was given, else 2, 4 ... (halved to fit the GPU).
std::size_t uploadFactor(const GridVolumeGL& gl) {
  const auto& whole = gl.unreducedGrid();
  if (!whole || gl.grid().nx == 0) return 1;
  const long halvings = std::lround(std::log2(static_cast<double>(whole->nx) / static_cast<double>(gl.grid().nx)));
  return std::size_t{1} << std::max(1L, halvings);
}

// "" for a grid drawn at its resolution, else "  at 1/2 resolution (GPU memory)" and so on.
std::string reducedNote(const GridVolumeGL& gl) {
  const std::size_t f = uploadFactor(gl);
  return f == 1 ? std::string() : "  at 1/" + std::to_string(f) + " resolution (GPU memory)";
}

}  // namespace

LegendPart GridSourceGL::legendPart() const {
  const volume::GridVolume& v = volume_->grid();
  std::string resolution;
  if (volume_->unreducedGrid()) {
    const std::size_t f = windowOrGridFactor();
    if (nearUsed_)
      resolution = "  the nearest columns at full resolution, the rest at 1/" + std::to_string(f) + " (GPU memory)";
    else if (viewWindow().empty()) resolution = reducedNote(*volume_);
    else
      resolution = f > 1 ? "  the columns in view at 1/" + std::to_string(f) + " resolution (GPU memory)"
                         : "  the columns in view at full resolution";
  }
  const std::string variable = displayName(v.variable);
  // A mosaic written by `atmoglobe mosaic` is a radar product at the radars' latest time.
  const std::string kind = mosaicRule_.empty() ? " (forecast grid)" : " (radar mosaic, " + mosaicRule_ + ")";
  return LegendPart{variable + kind,
                    variable + (mosaicRule_.empty() ? " valid " : " at ") + utcLabel(v.validTime) +
                        (volume::memberText(v).empty() ? std::string() : "  " + volume::memberText(v)) +
                        (volume::extraIndexText(v).empty() ? std::string() : "  " + volume::extraIndexText(v)) +
                        (v.approximateHeights ? "  (heights approximate)" : "") + resolution +
                        (detailLevel_ > 0 ? "  level of detail " + std::to_string(detailLevel_) + " (columns x" +
                                                std::to_string(volume::detailHorizontalFactor(detailLevel_)) + ")"
                                          : std::string()),
                    LegendKey{variable, v.units, options_.render.transfer.colors}, synthetic_};
}

LayerMemory GridSourceGL::memory() const {
  const volume::GridVolume& v = volume_->grid();
  std::uint64_t cpu = (v.values.size() + v.heightAboveEllipsoidMeters.size()) * sizeof(float) +
                      (v.lonDeg.size() + v.latDeg.size()) * sizeof(double);
  std::uint64_t gpu = volume_->gpuBytes();
  if (window_ && window_->of == volume_->id()) {
    cpu += volume::gridVolumeBytes(window_->volume->grid());
    gpu += window_->volume->gpuBytes();
  }
  if (near_ && near_->of == volume_->id()) {
    cpu += volume::gridVolumeBytes(near_->volume->grid());
    gpu += near_->volume->gpuBytes();
  }
  if (const auto& whole = volume_->unreducedGrid()) cpu += volume::gridVolumeBytes(*whole);
  if (detailOf_ == volume_.get())
    for (const auto& d : detail_)
      if (d) {
        cpu += volume::gridVolumeBytes(d->grid());
        gpu += d->gpuBytes();
      }
  return LayerMemory{"grid " + v.variable, cpu, gpu};
}

std::vector<const VolumeGL*> GridSourceGL::volumes() const {
  if (detailLevel_ > 0 && detailOf_ == volume_.get() && static_cast<std::size_t>(detailLevel_) <= detail_.size() &&
      detail_[static_cast<std::size_t>(detailLevel_) - 1])
    return {detail_[static_cast<std::size_t>(detailLevel_) - 1].get()};
  if (nearUsed_) return {near_->volume.get(), &windowOrGrid()};
  return {&windowOrGrid()};
}

const GridVolumeGL& GridSourceGL::windowOrGrid() const {
  return windowUsed_ && window_ && window_->of == volume_->id() ? *window_->volume : *volume_;
}

std::size_t GridSourceGL::windowOrGridFactor() const {
  // A window's own factor, times what its upload halved it by where it did not fit either.
  const GridVolumeGL& drawn = windowOrGrid();
  return &drawn == volume_.get() ? uploadFactor(drawn) : window_->factor * uploadFactor(drawn);
}

std::optional<volume::LonLatBox> GridSourceGL::holeOf(const VolumeGL* volume) const {
  if (nearUsed_ && volume == &windowOrGrid()) return nearBox_;
  return std::nullopt;
}

volume::GridWindow GridSourceGL::viewWindow() const {
  if (window_ && volumes().back() == window_->volume.get()) return window_->window;
  return {};
}

void GridSourceGL::chooseDetail(const Camera& camera, bool background) {
  chooseCoarserCopy(camera, background);
  chooseViewWindow(camera, background);
  chooseNearWindow(camera, background);
}

namespace {

// True when `inner` lies inside `outer` (columns modulo nx: windows may cross a wrapping grid's seam).
bool windowContains(const volume::GridWindow& outer, const volume::GridWindow& inner, std::size_t nx) {
  if (inner.firstRow < outer.firstRow || inner.firstRow + inner.rowCount > outer.firstRow + outer.rowCount)
    return false;
  const std::size_t offset = (inner.firstColumn + nx - outer.firstColumn % nx) % nx;
  return offset + inner.columnCount <= outer.columnCount;
}

// `w` widened by an eighth of its size (at least 2 points) on each side, within the grid.
volume::GridWindow widenWindow(const volume::GridWindow& w, const volume::GridVolume& g) {
  volume::GridWindow out;
  const std::size_t mr = std::max<std::size_t>(2, w.rowCount / 8), mc = std::max<std::size_t>(2, w.columnCount / 8);
  out.firstRow = w.firstRow >= mr ? w.firstRow - mr : 0;
  out.rowCount = std::min(g.ny, w.firstRow + w.rowCount + mr) - out.firstRow;
  if (g.wrapsLongitude) {
    out.columnCount = std::min(g.nx, w.columnCount + 2 * mc);
    out.firstColumn = out.columnCount == g.nx ? 0 : (w.firstColumn + g.nx - mc % g.nx) % g.nx;
  } else {
    out.firstColumn = w.firstColumn >= mc ? w.firstColumn - mc : 0;
    out.columnCount = std::min(g.nx, w.firstColumn + w.columnCount + mc) - out.firstColumn;
  }
  return out;
}

}  // namespace

namespace {

bool sameWindow(const volume::GridWindow& a, const volume::GridWindow& b) {
  return a.firstColumn == b.firstColumn && a.columnCount == b.columnCount && a.firstRow == b.firstRow &&
         a.rowCount == b.rowCount;
}

// What a window in view depends on of a camera.
std::vector<double> cameraKey(const Camera& camera) {
  const CameraPose& pose = camera.pose();
  return {pose.latDeg,
          pose.lonDeg,
          pose.heightMeters,
          pose.headingDeg,
          pose.pitchDeg,
          pose.rollDeg,
          camera.fovYDeg(),
          static_cast<double>(camera.widthPx()),
          static_cast<double>(camera.heightPx())};
}

// The latitude/longitude box a rectilinear window's grid has data in: its first to last column's
// longitude (increasing across the seam; a near window never wraps: nearGridWindow), its rows'
// latitudes.
volume::LonLatBox windowBox(const volume::GridVolume& w) {
  volume::LonLatBox box;
  box.westDeg = w.lonDeg.front();
  box.spanDeg = w.lonDeg.back() - w.lonDeg.front();
  box.southDeg = std::min(w.latDeg.front(), w.latDeg.back());
  box.northDeg = std::max(w.latDeg.front(), w.latDeg.back());
  return box;
}

}  // namespace

void GridSourceGL::chooseNearWindow(const Camera& camera, bool background) {
  nearUsed_ = false;
  if (near_ && near_->of != volume_->id()) near_.reset();  // another step or a reload
  if (nearBuilding_ && nearBuilding_->prepared.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    std::shared_ptr<const GridVolumeGL::Prepared> prepared = nearBuilding_->prepared.get();
    if (prepared && nearBuilding_->of == volume_->id()) {
      // A window the GPU takes only at a lower resolution is no near window: not tried again.
      auto gl = GridVolumeGL::create(std::move(prepared));
      if (gl && !(*gl)->unreducedGrid())
        near_ = ViewWindow{nearBuilding_->of, nearBuilding_->window, 1, std::move(*gl)};
      else nearRefused_ = NearRefused{nearBuilding_->of, nearBuilding_->window};
    }
    nearBuilding_.reset();
  }
  const std::shared_ptr<const volume::GridVolume> whole = volume_->unreducedGrid();
  // Only where the coarser level is coarser than the grid (rectilinear grids: the hole is a
  // latitude/longitude box); otherwise what there is is dropped.
  const std::size_t coarseFactor = windowOrGridFactor();
  if (!description_.nearWindow || !whole || whole->reduced() || whole->curvilinear || !description_.levelOfDetail ||
      detailLevel_ > 0 || coarseFactor <= 1) {
    near_.reset();
    return;
  }
  if (const std::vector<double> key = cameraKey(camera); key != nearKey_ || nearOf_ != whole.get()) {
    nearKey_ = key;
    nearOf_ = whole.get();
    // No more columns x rows than the grid as uploaded, nor columns or rows than its texture.
    const volume::GridVolume& uploaded = volume_->grid();
    nearInSight_ = nearGridWindow(camera, *whole, uploaded.nx * uploaded.ny, uploaded.nx, uploaded.ny);
  }
  const volume::GridWindow wanted = nearInSight_;
  if (wanted.empty()) return;
  const bool refused = nearRefused_ && nearRefused_->of == volume_->id() && sameWindow(nearRefused_->window, wanted);
  // The window there is serves while it holds the middle half of the one wanted (each side an
  // eighth of a move keeps it); meanwhile a new one is made.
  volume::GridWindow middle = wanted;
  middle.firstRow += wanted.rowCount / 4, middle.rowCount -= 2 * (wanted.rowCount / 4);
  middle.firstColumn = (wanted.firstColumn + wanted.columnCount / 4) % whole->nx;
  middle.columnCount -= 2 * (wanted.columnCount / 4);
  const bool holds = near_ && windowContains(near_->window, middle, whole->nx);
  if (!holds && !refused) {
    auto make = [whole, wanted]() -> std::shared_ptr<const GridVolumeGL::Prepared> {
      auto part = volume::gridWindow(*whole, wanted);
      if (!part || !GridVolumeGL::checkDrawable(*part)) return nullptr;
      return GridVolumeGL::prepare(*part);
    };
    if (background) {
      if (!nearBuilding_) nearBuilding_ = WindowBuild{volume_->id(), wanted, 1, std::async(std::launch::async, make)};
    } else if (std::shared_ptr<const GridVolumeGL::Prepared> prepared = make()) {
      auto gl = GridVolumeGL::create(std::move(prepared));
      if (gl && !(*gl)->unreducedGrid()) near_ = ViewWindow{volume_->id(), wanted, 1, std::move(*gl)};
      else nearRefused_ = NearRefused{volume_->id(), wanted};
    } else {
      nearRefused_ = NearRefused{volume_->id(), wanted};
    }
  }
  if (!near_) return;  // until one is made, the coarser level alone
  nearBox_ = windowBox(near_->volume->grid());
  nearUsed_ = true;
}

void GridSourceGL::chooseViewWindow(const Camera& camera, bool background) {
  windowUsed_ = false;
  if (window_ && window_->of != volume_->id()) window_.reset();  // another step or a reload
  if (windowBuilding_ && windowBuilding_->prepared.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    std::shared_ptr<const GridVolumeGL::Prepared> prepared = windowBuilding_->prepared.get();
    if (prepared && windowBuilding_->of == volume_->id())
      if (auto gl = GridVolumeGL::create(std::move(prepared)))
        window_ = ViewWindow{windowBuilding_->of, windowBuilding_->window, windowBuilding_->factor, std::move(*gl)};
    windowBuilding_.reset();
  }
  const std::shared_ptr<const volume::GridVolume> whole = volume_->unreducedGrid();
  if (!whole || !description_.levelOfDetail || detailLevel_ > 0) return;
  // The window in view is found again only when the camera changed (a 0.25-degree grid: some
  // 40,000 points projected).
  const std::vector<double> key = cameraKey(camera);
  if (key != viewKey_ || viewOf_ != whole.get()) {
    viewKey_ = key;
    viewOf_ = whole.get();
    viewInSight_ = visibleGridWindow(camera, *whole);
  }
  const volume::GridWindow view = viewInSight_;
  if (view.empty()) return;
  // The window's resolution: the finest (every `factor`-th column and row, factor 1, 2, 4 ...)
  // at which the window in view (widened) has no more columns x rows than the grid as uploaded,
  // so that it fits where that did; worth making only while finer than the grid as uploaded
  // (every `uploaded`-th column). Levels as uploaded.
  const volume::GridVolume& drawnWhole = volume_->grid();
  const std::size_t uploaded =
      std::size_t{1} << std::max(0L,
                                 std::lround(std::log2(static_cast<double>(whole->nx) /
                                                       static_cast<double>(std::max<std::size_t>(1, drawnWhole.nx)))));
  auto pointsAt = [](const volume::GridWindow& w, std::size_t f) {
    return ((w.columnCount + f - 1) / f) * ((w.rowCount + f - 1) / f);
  };
  auto factorFor = [&](const volume::GridWindow& w) {
    std::size_t f = 1;
    while (f < uploaded && pointsAt(w, f) > drawnWhole.nx * drawnWhole.ny) f *= 2;
    return f;
  };
  // The window made for this view would keep every `factor`-th point: the one there is serves
  // while it holds the view at that resolution or finer (a closer view makes a finer one).
  const volume::GridWindow window = widenWindow(view, *whole);
  const std::size_t factor = factorFor(window);
  if (window_ && windowContains(window_->window, view, whole->nx) && window_->factor <= factor) {
    windowUsed_ = true;
    return;
  }
  if (factor >= uploaded) return;
  const bool levels = drawnWhole.nz < whole->nz;
  auto make = [whole, window, factor, levels]() -> std::shared_ptr<const GridVolumeGL::Prepared> {
    // A reduced grid's rows lengthened so that every factor-th point still reaches the east edge.
    auto part = volume::gridWindow(*whole, window, factor);
    if (!part) return nullptr;
    if (factor > 1) *part = volume::decimateGrid(*part, factor, levels);
    if (!GridVolumeGL::checkDrawable(*part)) return nullptr;
    return GridVolumeGL::prepare(*part);
  };
  if (background) {  // until it is made, the grid as uploaded
    if (!windowBuilding_)
      windowBuilding_ = WindowBuild{volume_->id(), window, factor, std::async(std::launch::async, make)};
    return;
  }
  std::shared_ptr<const GridVolumeGL::Prepared> prepared = make();
  if (!prepared) return;
  auto gl = GridVolumeGL::create(std::move(prepared));
  if (!gl) return;
  window_ = ViewWindow{volume_->id(), window, factor, std::move(*gl)};
  windowUsed_ = true;
}

void GridSourceGL::chooseCoarserCopy(const Camera& camera, bool background) {
  if (detailOf_ != volume_.get()) {  // another step or a reload: the copies were of the old grid
    detail_.assign(static_cast<std::size_t>(volume::maxDetailLevel(volume_->grid())), nullptr);
    detailOf_ = volume_.get();
  }
  // A copy made on the worker: uploaded here (GL thread) when done, dropped when of an old grid.
  if (building_ && building_->prepared.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    std::shared_ptr<const GridVolumeGL::Prepared> prepared = building_->prepared.get();
    if (prepared && building_->of == volume_->id())
      if (auto gl = GridVolumeGL::create(std::move(prepared)))
        detail_[static_cast<std::size_t>(building_->level) - 1] = std::move(*gl);
    building_.reset();
  }
  detailLevel_ = 0;
  if (!description_.levelOfDetail || detail_.empty()) return;
  // By the layer's own image scale, not the viewer's lower one while moving: a moving frame then
  // marches what the frame at rest will (its image is the refinement's preview), and no copy is
  // made in the middle of a flight (measured: on 2 cores the worker slowed the moving frames).
  const int level =
      std::min(gridDetailLevelFor(*volume_, camera, description_.imageScale), static_cast<int>(detail_.size()));
  if (level == 0) return;
  std::shared_ptr<GridVolumeGL>& wanted = detail_[static_cast<std::size_t>(level) - 1];
  if (!wanted && background) {
    // Made meanwhile (block means and tables: 0.1-0.5 s for a global 0.25-degree grid); until
    // then the nearest finer copy made, else the grid itself.
    if (!building_) {
      std::shared_ptr<const GridVolumeGL> source = volume_;
      building_ = DetailBuild{
          level, volume_->id(),
          std::async(std::launch::async, [source, level]() -> std::shared_ptr<const GridVolumeGL::Prepared> {
            const volume::GridVolume& g = source->grid();
            auto coarse =
                volume::coarsenGrid(g, volume::detailHorizontalFactor(level), volume::detailVerticalFactor(g, level));
            if (!coarse || !GridVolumeGL::checkDrawable(*coarse)) return nullptr;
            return GridVolumeGL::prepare(*coarse);
          })};
    }
    for (int l = level - 1; l > 0; --l)
      if (detail_[static_cast<std::size_t>(l) - 1]) {
        detailLevel_ = l;
        return;
      }
    return;
  }
  for (int l = level; l > 0; --l) {  // the level wanted, or the finest coarser one that can be made
    std::shared_ptr<GridVolumeGL>& slot = detail_[static_cast<std::size_t>(l) - 1];
    if (!slot) {
      auto gl = createGridDetail(volume_->grid(), l);
      if (!gl) continue;
      slot = std::move(*gl);
    }
    detailLevel_ = l;
    return;
  }
}

int gridDetailLevelFor(const GridVolumeGL& grid, const Camera& camera, double imageScale) {
  const auto* sampler = dynamic_cast<const volume::GridSampler*>(&grid.referenceSampler());
  if (!sampler) return 0;
  // The footprint of a pixel where the grid is nearest the eye: the finest any of its pixels needs.
  const volume::BoundingSphere sphere = sampler->boundingSphere();
  const double distance = glm::length(camera.eyeEcef() - sphere.centreEcef) - sphere.radiusMeters;
  const double footprint = volume::pixelFootprintMeters(distance, camera.fovYDeg(), camera.heightPx(), imageScale);
  return volume::gridDetailLevel(sampler->cellScale().columnSpacingMeters, footprint,
                                 volume::maxDetailLevel(grid.grid()));
}

Result<std::unique_ptr<GridVolumeGL>> createGridDetail(const volume::GridVolume& grid, int level) {
  auto coarse =
      volume::coarsenGrid(grid, volume::detailHorizontalFactor(level), volume::detailVerticalFactor(grid, level));
  if (!coarse) return coarse.forwardError();
  return GridVolumeGL::create(*coarse);
}

std::optional<std::string> GridSourceGL::readoutAt(const glm::dvec3& eye, const glm::dvec3& dir, double tMaxMeters,
                                                   double stepMeters) const {
  // The grid itself, or its window in view at full resolution where it is drawn from one (not the
  // coarser copies of the level of detail: the readout gives the data's values).
  const GridVolumeGL& shown = windowOrGrid();
  // Where a near window is drawn: the coarser level (shown) outside its box, the near window
  // inside, the nearer hit.
  const volume::SamplerOutsideBox holed(shown.referenceSampler(), nearBox_);
  auto hit = firstValueAlong(nearUsed_ ? static_cast<const volume::VolumeSampler&>(holed) : shown.referenceSampler(),
                             eye, dir, tMaxMeters, stepMeters, volume::Interpolation::Linear);
  if (nearUsed_) {
    auto nearHit = firstValueAlong(near_->volume->referenceSampler(), eye, dir, tMaxMeters, stepMeters,
                                   volume::Interpolation::Linear);
    if (nearHit && (!hit || glm::length(nearHit->ecef - eye) <= glm::length(hit->ecef - eye))) hit = nearHit;
  }
  if (!hit) return std::nullopt;
  const volume::GridVolume& v = volume_->grid();
  const globe::Geodetic g = globe::ecefToGeodetic(hit->ecef);
  char text[320];
  std::snprintf(text, sizeof text,
                "%.4g %s  (at %.3f, %.3f, drawn height %.0f m above the ellipsoid, %.0f m above sea level)", hit->value,
                v.units.c_str(), g.latDeg, g.lonDeg, g.heightMeters, seaLevelHeightMeters(g));
  std::string line = displayName(v.variable) + ": " + text;
  if (!v.ensembleStatistic.empty()) {
    line += " (" + v.ensembleStatistic + ")";
    const MemberGrids& m = memberGrids();
    if (!m.note.empty()) {
      line.append("\n  members: ");
      line.append(m.note);
      return line;
    }
    std::vector<std::pair<long, double>> values;
    for (std::size_t k = 0; k < m.grids.size(); ++k) {
      const volume::VolumeSample s = m.samplers[k]->sample(hit->ecef, volume::Interpolation::Linear);
      values.emplace_back(m.grids[k].first, s.state == volume::VolumeSample::State::Echo
                                                ? s.value
                                                : std::numeric_limits<double>::quiet_NaN());
    }
    line.push_back('\n');
    line.append(memberValuesLine(values));
  }
  return line;
}

const GridSourceGL::MemberGrids& GridSourceGL::memberGrids() const {
  if (members_ && members_->volume == volume_.get()) return *members_;
  auto m = std::make_shared<MemberGrids>();
  m->volume = volume_.get();
  const volume::GridVolume& v = volume_->grid();
  volume::GridReadOptions read = gridReadOptions(description_);
  read.ensemble.reset();
  read.timeIndex = step_;
  read.timeIso8601.clear();
  auto selections = volume::ensembleMemberSelections(description_.path, read);
  // Kept only within a quarter of the memory budget: each member is the statistic's size.
  const std::uint64_t each = volume::gridVolumeBytes(v);
  if (!selections) {
    m->note = selections.error();
  } else if (each * selections->size() > volume::defaultMemoryBudgetBytes() / 4) {
    m->note = std::to_string(selections->size()) + " members of " + std::to_string(each >> 20) +
              " MiB each: more than a quarter of the memory budget, not kept for the readout";
  } else {
    for (const volume::EnsembleMemberSelection& sel : *selections) {
      volume::GridReadOptions r = read;
      r.member = sel.member;
      for (const auto& [dimension, index] : sel.extraIndex) r.extraIndex[dimension] = index;
      auto one = volume::readGridVolume(description_.path, r);
      Status cut = one ? cropGridLayer(description_, *one) : Status(one.forwardError());  // as the statistic's
      if (cut && one->values.size() != v.values.size()) cut = makeError("a member's grid differs from the statistic's");
      if (!cut) {
        m->note = cut.error();
        m->grids.clear();
        break;
      }
      const long label = volume::memberLabel(*one, static_cast<long>(m->grids.size()));
      // The statistic's geometry and drawn (exaggerated) heights with this member's values: a
      // point is then sampled at the same place in every member.
      volume::GridVolume member = v;
      member.values = std::move(one->values);
      volume::setValueRange(member);
      m->grids.emplace_back(label, std::move(member));
    }
  }
  for (const auto& grid : m->grids) m->samplers.push_back(std::make_unique<volume::GridSampler>(grid.second));
  members_ = std::move(m);
  return *members_;
}

std::string GridSourceGL::loadNote() const {
  const volume::GridVolume& g = volume_->grid();
  std::ostringstream text;
  text << description_.path << ": " << g.variable << (g.units.empty() ? "" : " [" + g.units + "]") << " at "
       << (g.validTime.empty() ? std::string("(no time axis)") : g.validTime)
       << (volume::memberText(g).empty() ? std::string() : ", " + volume::memberText(g))
       << (volume::extraIndexText(g).empty() ? std::string() : ", " + volume::extraIndexText(g)) << ", " << g.nx
       << " x " << g.ny << " x " << g.nz << ", " << static_cast<double>(g.bytesRead) / 1048576.0
       << " MiB read; heights: " << g.heightNote << (g.approximateHeights ? " (APPROXIMATE)" : "");
  return text.str();
}

}  // namespace atmoglobe::engine
