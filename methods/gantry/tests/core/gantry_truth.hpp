// An independent ground truth for the M2 gantry tests: a gantry machine with
// four AC-head sub-machines (beam, two columns, floor bridge) whose geometry is
// built so that every quantity the module computes is known BY CONSTRUCTION
// (long double, no solving):
//  - the three reference planes all pass through the chosen origin O;
//  - the A axis passes through T + offset * unit(c x a), so the common
//    perpendicular of C and A has its foot on C exactly at the chosen wrist
//    centre T and its length is the chosen offset;
//  - each linear axis, the gantry and each circle are sampled from the chosen
//    direction / rotation, as a tracker would see a target moved along them.
// The frames' definitions (S1 and S4 cross products) are restated here from
// docs/METHODS.md. Points are written in the tracker's frame, tracker at its origin.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "reference.hpp"
#include "trueaxis/core/gantry_frames.hpp"

namespace trueaxis::test {

constexpr long double kArcsecL = kPiL / (180.0L * 3600.0L);

inline Vec3L unit_l(const Vec3L& v) { return v / v.norm(); }

// A small rotation of `v` by `arcsec` about a random axis perpendicular to it.
inline Vec3L tilt_l(const Vec3L& v, long double arcsec, Rng& rng) {
  const Vec3L axis = unit_l(v.cross(rng.unit_vector().cast<long double>()));
  return rodrigues_l(axis * arcsec * kArcsecL) * v;
}

struct TrueSub {
  int id = 0;
  Vec3L dirs[3];        // measured axes x, y, z (global)
  long double stroke[3] = {0, 0, 0};
  Vec3L pass_start[3];  // where the target starts on each axis (global)
  Vec3L wrist;          // T (global)
  Vec3L c;              // C axis direction, towards the tool tip (global)
  Vec3L a;              // A axis direction, positive rotation (global)
  long double offset = 0, swing = 0;
  Vec3L tool_nominal;   // global
  bool c_turns_negative = false;  // C measured turning about -c
  core::Axis master = core::Axis::kX;
  // Expected results (global frame).
  Mat3L R;              // columns x', y', z'
  Vec3L origin;         // O_sp
  Vec3L squareness_arcsec;
  long double ac_angle_deg = 0;
};

struct TrueGantry {
  Mat3L R_tg;  // tracker_T_global
  Vec3L O_t;
  Vec3L z0_t, n1_t, n2_t;  // bed and side normals (tracker)
  std::array<TrueSub, 4> subs;
};

// S4 restated (docs/METHODS.md): the master axis kept, the others by cross products.
inline Mat3L s4_frame(const Vec3L d[3], core::Axis master) {
  Vec3L x = d[0], y = d[1], z = d[2];
  if (master == core::Axis::kX) {
    y = unit_l(z.cross(x));
    z = x.cross(y);
  } else if (master == core::Axis::kY) {
    x = unit_l(y.cross(z));
    z = x.cross(y);
  } else {
    x = unit_l(y.cross(z));
    y = z.cross(x);
  }
  Mat3L r;
  r << x, y, z;
  return r;
}

inline TrueGantry make_truth(Rng& rng) {
  TrueGantry g;
  // S1: the bed tilted 40" from the tracker's +Z, the gantry yawed 37 deg and 15"
  // off perpendicular to the bed normal.
  g.z0_t = tilt_l(Vec3L::UnitZ(), 40.0L, rng);
  const long double yaw = deg_l(37.0L);
  const Vec3L h(std::cos(yaw), std::sin(yaw), 0.0L);
  const Vec3L h_in = unit_l(h - h.dot(g.z0_t) * g.z0_t);
  const Vec3L x = rodrigues_l(unit_l(g.z0_t.cross(h_in)) * (-15.0L * kArcsecL)) * h_in;
  const Vec3L y = unit_l(g.z0_t.cross(x));
  g.R_tg << x, y, x.cross(y);
  // The tracker stands at global (3000, -2000, 1200).
  g.O_t = -(g.R_tg * Vec3L(3000, -2000, 1200));
  const Vec3L ex = unit_l(x - x.dot(g.z0_t) * g.z0_t);  // in the bed plane
  g.n1_t = tilt_l(-ex, 60.0L, rng);                        // face at the X = 0 end
  g.n2_t = tilt_l(-g.z0_t.cross(ex), 60.0L, rng);          // face at the Y = 0 side

  struct Layout {
    Vec3L wrist, tool, a_nominal;
    long double swing, stroke[3];
    bool c_negative;
  };
  const Layout layouts[4] = {
      {Vec3L(2500, 1500, 1800), -Vec3L::UnitZ(), Vec3L::UnitX(), 300, {400, 2500, 600}, false},   // beam
      {Vec3L(3000, 150, 900), Vec3L::UnitY(), Vec3L::UnitZ(), 250, {300, 500, 1800}, true},       // left column
      {Vec3L(3500, 2850, 1000), -Vec3L::UnitY(), Vec3L::UnitX(), 220, {350, 450, 1700}, false},  // right column
      {Vec3L(4000, 1500, 300), Vec3L::UnitZ(), Vec3L::UnitY(), 380, {1200, 800, 300}, false},     // floor bridge
  };
  for (int i = 0; i < 4; ++i) {
    const Layout& l = layouts[i];
    TrueSub& s = g.subs[static_cast<std::size_t>(i)];
    s.id = i + 1;
    for (int k = 0; k < 3; ++k) {
      s.dirs[k] = tilt_l(Vec3L::Unit(k), rng.uniform(10.0, 40.0), rng);
      s.stroke[k] = l.stroke[k];
      s.pass_start[k] = l.wrist + Vec3L(rng.uniform(-100, 100), rng.uniform(-100, 100), rng.uniform(-100, 100)) -
                        0.5L * l.stroke[k] * s.dirs[k];
    }
    s.master = l.stroke[0] >= l.stroke[1] && l.stroke[0] >= l.stroke[2] ? core::Axis::kX
               : l.stroke[1] >= l.stroke[2]                             ? core::Axis::kY
                                                                        : core::Axis::kZ;
    s.wrist = l.wrist;
    s.tool_nominal = l.tool;
    s.c = tilt_l(l.tool, rng.uniform(10.0, 40.0), rng);
    s.a = tilt_l(l.a_nominal, rng.uniform(10.0, 40.0), rng);
    s.offset = rng.uniform(0.01, 0.05);
    s.swing = l.swing;
    s.c_turns_negative = l.c_negative;
    s.R = s4_frame(s.dirs, s.master);
    s.origin = s.wrist + s.swing * s.c;
    for (int k = 0; k < 3; ++k) {
      s.squareness_arcsec(k) = (angle_l(s.dirs[k], s.dirs[(k + 1) % 3]) - kPiL / 2) / kArcsecL;
    }
    s.ac_angle_deg = angle_l(s.a, s.c) * 180.0L / kPiL;
  }
  return g;
}

// Tracker-frame point lists, one vector per group.
struct Samples {
  std::vector<core::Vec3> bed, side_1, side_2;
  std::vector<std::vector<core::Vec3>> gantry;
  struct Sub {
    std::vector<std::vector<core::Vec3>> passes[3];
    std::vector<core::Vec3> c, a;
  };
  std::array<Sub, 4> subs;
};

struct NoiseSpec {
  double a_mm = 0.0;       // distance term, 1 sigma per axis
  double b_per_mm = 0.0;   // range term
  bool global_only = false;  // noise only on the bed, sides and gantry
};

// AT960-like MPE +-(15 um + 6 um/m) read as 2 sigma.
inline constexpr NoiseSpec kTracker{0.0075, 3e-6, false};

class Sampler {
 public:
  Sampler(const TrueGantry& g, Rng& rng, NoiseSpec noise) : g_(g), rng_(rng), noise_(noise) {}

  // Tracker-frame point for a global point, with the tracker's noise.
  core::Vec3 measure(const Vec3L& p_global, bool noisy) {
    const Vec3L p = g_.R_tg * p_global + g_.O_t;
    core::Vec3 q = p.cast<double>();
    if (noisy && (noise_.a_mm > 0 || noise_.b_per_mm > 0)) {
      const double s = std::hypot(noise_.a_mm, noise_.b_per_mm * q.norm());
      q += s * core::Vec3(rng_.normal(), rng_.normal(), rng_.normal());
    }
    return q;
  }
  // A tracker-frame point (for the planes, built in the tracker frame).
  core::Vec3 measure_t(const Vec3L& p_t, bool noisy) { return measure(g_.R_tg.transpose() * (p_t - g_.O_t), noisy); }

  Samples sample() {
    Samples s;
    const bool gn = true;
    const bool sn = !noise_.global_only;
    const Vec3L ex = unit_l(g_.R_tg.col(0) - g_.R_tg.col(0).dot(g_.z0_t) * g_.z0_t);
    const Vec3L ey = g_.z0_t.cross(ex);
    const long double pads[4][2] = {{60, 60}, {5860, 60}, {5860, 2860}, {60, 2860}};
    for (const auto& pad : pads) {
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          s.bed.push_back(measure_t(g_.O_t + (pad[0] + 40 * i) * ex + (pad[1] + 40 * j) * ey, gn));
        }
      }
    }
    side(g_.n1_t, ey, s.side_1, gn);
    side(g_.n2_t, ex, s.side_2, gn);
    for (int k = 0; k < 3; ++k) {
      std::vector<core::Vec3> pass;
      for (int i = 0; i < 30; ++i) pass.push_back(measure(Vec3L(100 + 200.0L * i, 1500, 2300), gn));
      s.gantry.push_back(pass);
    }
    for (std::size_t i = 0; i < 4; ++i) {
      const TrueSub& t = g_.subs[i];
      Samples::Sub& out = s.subs[i];
      for (int k = 0; k < 3; ++k) {
        for (int pass = 0; pass < 3; ++pass) {
          std::vector<core::Vec3> p;
          for (int j = 0; j <= 20; ++j) p.push_back(measure(t.pass_start[k] + (t.stroke[k] * j / 20) * t.dirs[k], sn));
          out.passes[k].push_back(p);
        }
      }
      // C: a target 120 mm off the axis, 100 mm above the tool tip; 24 positions.
      const Vec3L off = unit_l(t.c.cross(Vec3L(0.3L, 0.5L, 0.7L)));
      const Vec3L target_c = t.wrist + (t.swing - 100) * t.c + 120 * off;
      const Vec3L c_turn = t.c_turns_negative ? Vec3L(-t.c) : t.c;
      for (int j = 0; j < 24; ++j) {
        const long double th = deg_l(-172.5L + 15.0L * j);
        out.c.push_back(measure(t.wrist + rodrigues_l(th * c_turn) * (target_c - t.wrist), sn));
      }
      // A: the same target while A turns -90..90 deg about its own line.
      const Vec3L a_point = t.wrist + t.offset * unit_l(t.c.cross(t.a));
      for (int j = 0; j <= 18; ++j) {
        const long double th = deg_l(-90.0L + 10.0L * j);
        out.a.push_back(measure(a_point + rodrigues_l(th * t.a) * (target_c - a_point), sn));
      }
    }
    return s;
  }

 private:
  // A side face through O with normal n, sampled 10..80 mm along `along` and
  // 10..55 mm below the bed.
  void side(const Vec3L& n, const Vec3L& along, std::vector<core::Vec3>& out, bool noisy) {
    const Vec3L w1 = unit_l(along - along.dot(n) * n);
    const Vec3L w2 = n.cross(w1).dot(g_.z0_t) < 0 ? Vec3L(n.cross(w1)) : Vec3L(-n.cross(w1));
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 3; ++j) out.push_back(measure_t(g_.O_t + (10 + 23.0L * i) * w1 + (10 + 22.5L * j) * w2, noisy));
    }
  }

  const TrueGantry& g_;
  Rng& rng_;
  NoiseSpec noise_;
};

inline core::PointSpan span(const std::vector<core::Vec3>& v) { return {v.data(), v.size()}; }

// The module's input over `s` (which must outlive it).
inline core::GantryInput make_input(const TrueGantry& g, const Samples& s) {
  core::GantryInput in;
  in.bed = span(s.bed);
  in.side_1 = span(s.side_1);
  in.side_2 = span(s.side_2);
  for (std::size_t k = 0; k < s.gantry.size(); ++k) in.gantry_passes[k] = span(s.gantry[k]);
  in.gantry_pass_count = s.gantry.size();
  for (std::size_t i = 0; i < 4; ++i) {
    core::SubMachineInput& sub = in.sub_machines[i];
    const TrueSub& t = g.subs[i];
    sub.id = t.id;
    for (int k = 0; k < 3; ++k) {
      for (std::size_t p = 0; p < s.subs[i].passes[k].size(); ++p) sub.passes[k][p] = span(s.subs[i].passes[k][p]);
      sub.pass_count[k] = s.subs[i].passes[k].size();
    }
    sub.c_circle = span(s.subs[i].c);
    sub.a_circle = span(s.subs[i].a);
    sub.swing_mm = static_cast<double>(t.swing);
    sub.tool_direction = (g.R_tg * t.tool_nominal).cast<double>();
  }
  in.sub_machine_count = 4;
  return in;
}

}  // namespace trueaxis::test
