// The traverse of a linear winding machine: the wire guide (the supply's
// port) moves along the core axis by a pitch per core turn, geared to the
// spindle, and reverses at the ends of the winding width, layer after layer.
//
// The port starts over the first turn's centre, half a wire diameter from
// the first flange; the turns' centres lie between d / 2 and W - d / 2 from
// it, so the port travels W - d between reversals (W the winding width, d
// the wire diameter). After `layers` passes it stays at the end of the last
// one. With no width the port keeps going: a spiral (today's
// process.traverse_pitch alone). Before the start (the core turned back
// past its starting angle) the first pass's line continues. A stalled
// traverse (a machine fault) stays where it is for `stall_rad` of core
// angle from `stall_from_rad`, then goes on from there.
#pragma once

#include <cmath>

namespace cws {

struct TraverseProfile {
  double pitch = 0.0;   // port travel along the core axis per core turn [m]; its sign: the first
                        // pass's direction
  double travel = 0.0;  // port travel between reversals, W - d [m]; 0: no reversal
  int layers = 0;       // passes before the port stops; 0: no end
  double stall_from_rad = 0.0;  // core angle at which the traverse stops [rad]
  double stall_rad = 0.0;       // core angle it stays stopped for [rad]; 0: never stops

  struct Position {
    double offset = 0.0;   // along the core axis from the start [m]
    double per_rad = 0.0;  // d offset / d core angle [m/rad]
    int layer = 0;         // 0 for the first pass
  };

  // The profile of a winding width [m] (0: none) for a wire of diameter
  // [m]: its travel is W - d.
  static TraverseProfile of(double pitch, double width, double diameter, int layers) {
    return TraverseProfile{pitch, width > 0.0 ? width - diameter : 0.0, layers};
  }
  // The same with a stall from core turn `from_turn` for `turns` turns [-].
  TraverseProfile stalled(double from_turn, double turns) const {
    TraverseProfile p = *this;
    p.stall_from_rad = 2.0 * M_PI * from_turn;
    p.stall_rad = 2.0 * M_PI * turns;
    return p;
  }

  // Where the port is when the core has turned by angle_rad [rad] from the
  // start.
  Position at(double angle_rad) const {
    // Within a stall: where it stopped, at rest; after it, the angle the
    // traverse has moved through.
    bool stopped = false;
    if (stall_rad > 0.0 && angle_rad > stall_from_rad) {
      stopped = angle_rad < stall_from_rad + stall_rad;
      angle_rad = stopped ? stall_from_rad : angle_rad - stall_rad;
    }
    Position p = moving(angle_rad);
    if (stopped) p.per_rad = 0.0;
    return p;
  }

 private:
  Position moving(double angle_rad) const {
    const double per_rad = pitch / (2.0 * M_PI);
    const double u = std::abs(per_rad) * angle_rad;  // travel so far [m]
    const double sign = pitch < 0.0 ? -1.0 : 1.0;
    Position p;
    if (travel <= 0.0 || u <= 0.0) {
      p.offset = sign * u;
      p.per_rad = per_rad;
      return p;
    }
    double pass = std::floor(u / travel);
    double along = u - pass * travel;
    double rate = std::abs(per_rad);
    if (layers > 0 && pass >= layers) {
      // Past the last layer: held at its end.
      pass = layers - 1;
      along = travel;
      rate = 0.0;
    }
    const bool forward = static_cast<long long>(pass) % 2 == 0;
    p.offset = sign * (forward ? along : travel - along);
    p.per_rad = sign * (forward ? rate : -rate);
    p.layer = static_cast<int>(pass);
    return p;
  }
};

}  // namespace cws
