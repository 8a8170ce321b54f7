#include "room_reverb/binaural/stream_pacer.h"

#include <cmath>

#include "room_reverb/common/error.h"

namespace room_reverb::core {

StreamPacer::StreamPacer(const StreamPacerOptions& options) : options_(options) {
  if (!(options.chunk_period_s > 0.0 && options.late_tolerance_s >= 0.0 &&
        options.max_lag_s >= options.late_tolerance_s && std::isfinite(options.max_lag_s))) {
    throw InputError("stream pacer: need chunk_period_s > 0 and 0 <= late_tolerance_s <= max_lag_s");
  }
}

StreamPacer::Step StreamPacer::next(double now) {
  Step step;
  if (!(now > 0.0)) {
    step.until = now + options_.chunk_period_s;
    return step;
  }
  if (!started_ || now < last_now_ - options_.chunk_period_s) {
    if (started_) ++counters_.restarts;
    started_ = true;
    start_ = now;
    index_ = 0;
  }
  last_now_ = now;
  const double due = dueTime(index_);
  if (now < due) {
    step.until = due;
    return step;
  }
  step.kind = Step::kRender;
  if (now - due > options_.max_lag_s) {
    // Resume with the chunk whose time is now.
    const auto current = static_cast<std::uint64_t>(std::floor((now - start_) / options_.chunk_period_s));
    step.dropped = current - index_;
    counters_.dropped += step.dropped;
    index_ = current;
  }
  return step;
}

void StreamPacer::published(double now) {
  if (now - dueTime(index_) > options_.late_tolerance_s) ++counters_.late;
  ++counters_.published;
  ++index_;
}

}  // namespace room_reverb::core
