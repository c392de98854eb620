#include "trueaxis/core/gantry_table.hpp"

#include <cmath>

#include "trueaxis/core/byte_order.hpp"

namespace trueaxis::core {

namespace {

// The one list of fields, in layout order, for both directions (byte_order.hpp).
template <typename Io, typename Rigid>
void rigid_fields(Io& io, Rigid& frame) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) io(frame.R(r, c));
  }
  io(frame.t);
}

template <typename Io, typename Global>
void global_fields(Io& io, Global& g) {
  rigid_fields(io, g.tracker_T_global);
  io(g.bed_flatness_mm);
  io(g.gantry_straightness_mm);
  io(g.origin_sigma_mm);
  io(g.angle_sigma_arcsec);
}

template <typename Io, typename Sub>
void sub_fields(Io& io, Sub& s) {
  rigid_fields(io, s.global_T_sub);
  io(s.origin_sigma_mm);
  io(s.angle_sigma_arcsec);
  io(s.squareness_arcsec);
  io(s.a_c_offset_mm);
  io(s.a_c_angle_deg);
  io(s.straightness_mm);
  io(s.c_circle_rms_mm);
  io(s.a_circle_rms_mm);
}

bool rotation(const Mat3& r) {
  return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() <= kGantryRotationTolerance &&
         std::abs(r.determinant() - 1.0) <= kGantryRotationTolerance;
}

bool nonnegative(const Vec3& v) { return v.minCoeff() >= 0.0; }

bool valid(const StoredGlobal& g) {
  return rotation(g.tracker_T_global.R) && g.bed_flatness_mm >= 0.0 && g.gantry_straightness_mm >= 0.0 &&
         g.origin_sigma_mm >= 0.0 && nonnegative(g.angle_sigma_arcsec);
}

bool valid(const StoredSubMachine& s) {
  return rotation(s.global_T_sub.R) && s.origin_sigma_mm >= 0.0 && nonnegative(s.angle_sigma_arcsec) &&
         s.a_c_offset_mm >= 0.0 && s.a_c_angle_deg >= 0.0 && s.a_c_angle_deg <= 180.0 &&
         nonnegative(s.straightness_mm) && s.c_circle_rms_mm >= 0.0 && s.a_circle_rms_mm >= 0.0;
}

std::uint8_t* sub_bytes(std::uint8_t* out, std::size_t i) {
  return out + kGantryHeaderBytes + kGantryGlobalBytes + i * kGantrySubBytes;
}
const std::uint8_t* sub_bytes(const std::uint8_t* in, std::size_t i) {
  return in + kGantryHeaderBytes + kGantryGlobalBytes + i * kGantrySubBytes;
}

}  // namespace

std::uint16_t GantryTable::id_mask() const {
  std::uint16_t mask = 0;
  for (std::size_t i = 0; i < kMaxSubMachines; ++i) {
    if (sub_machines[i].present) mask = static_cast<std::uint16_t>(mask | (1u << i));
  }
  return mask;
}

std::size_t GantryTable::count() const {
  std::size_t n = 0;
  for (const StoredSubMachine& s : sub_machines) n += s.present ? 1 : 0;
  return n;
}

StoredGlobal stored_global(const GlobalFrame& global) {
  StoredGlobal g;
  g.tracker_T_global = global.tracker_T_global;
  g.bed_flatness_mm = global.bed_flatness_mm;
  g.gantry_straightness_mm = global.gantry_straightness_mm;
  g.origin_sigma_mm = global.uncertainty.origin_sigma_mm;
  g.angle_sigma_arcsec = global.uncertainty.angle_sigma_arcsec;
  return g;
}

StoredSubMachine stored_sub_machine(const SubMachineFrame& f) {
  StoredSubMachine s;
  s.present = true;
  s.global_T_sub = f.global_T_sub;
  s.sub_T_global = inverse(f.global_T_sub);
  s.master_axis = f.master_axis;
  s.origin_sigma_mm = f.uncertainty.origin_sigma_mm;
  s.angle_sigma_arcsec = f.uncertainty.angle_sigma_arcsec;
  s.squareness_arcsec = f.squareness_arcsec;
  s.a_c_offset_mm = f.a_c_offset_mm;
  s.a_c_angle_deg = f.a_c_angle_deg;
  for (int k = 0; k < 3; ++k) s.straightness_mm(k) = f.straightness_mm[k];
  s.c_circle_rms_mm = f.c_circle.rms_distance_mm;
  s.a_circle_rms_mm = f.a_circle.rms_distance_mm;
  return s;
}

void merge_frames(GantryTable& table, const GantryFrames& frames) {
  table.global = stored_global(frames.global);
  for (std::size_t i = 0; i < frames.sub_machine_count; ++i) {
    const SubMachineFrame& f = frames.sub_machines[i];
    if (f.id >= 1 && f.id <= static_cast<int>(kMaxSubMachines)) {
      table.sub_machines[f.id - 1] = stored_sub_machine(f);
    }
  }
}

std::size_t encode_gantry_table(const GantryTable& table, std::uint8_t* out, std::size_t capacity) {
  const std::uint16_t mask = table.id_mask();
  if (out == nullptr || capacity < kGantryTableBytes || mask == 0) return 0;
  for (std::size_t k = 0; k < kGantryTableBytes; ++k) out[k] = 0;
  put_u16(out, kGantryLayoutVersion);
  put_u16(out + 2, mask);
  F64Writer w{out + kGantryHeaderBytes};
  StoredGlobal g = table.global;
  global_fields(w, g);
  for (std::size_t i = 0; i < kMaxSubMachines; ++i) {
    StoredSubMachine s = table.sub_machines[i];
    if (!s.present) continue;
    std::uint8_t* p = sub_bytes(out, i);
    p[0] = static_cast<std::uint8_t>(s.master_axis);
    F64Writer ws{p + 8};
    sub_fields(ws, s);
  }
  return kGantryTableBytes;
}

Status decode_gantry_table(const std::uint8_t* bytes, std::size_t size, GantryTable& out) {
  if (bytes == nullptr || size != kGantryTableBytes) return Status::kTableInvalid;
  const std::uint16_t mask = get_u16(bytes + 2);
  if (get_u16(bytes) != kGantryLayoutVersion || mask == 0 || mask >= (1u << kMaxSubMachines) ||
      get_u32(bytes + 4) != 0) {
    return Status::kTableInvalid;
  }
  for (std::size_t k = kGantryHeaderBytes; k < kGantryHeaderBytes + kGantryGlobalBytes; k += 8) {
    if (!std::isfinite(get_f64(bytes + k))) return Status::kTableInvalid;
  }
  // Check every value before `out` is touched.
  GantryTable t;
  F64Reader r{bytes + kGantryHeaderBytes};
  global_fields(r, t.global);
  if (!valid(t.global)) return Status::kTableInvalid;
  for (std::size_t i = 0; i < kMaxSubMachines; ++i) {
    const std::uint8_t* p = sub_bytes(bytes, i);
    if ((mask & (1u << i)) == 0) {
      for (std::size_t k = 0; k < kGantrySubBytes; ++k) {
        if (p[k] != 0) return Status::kTableInvalid;
      }
      continue;
    }
    if (p[0] > 2) return Status::kTableInvalid;
    for (std::size_t k = 1; k < 8; ++k) {
      if (p[k] != 0) return Status::kTableInvalid;
    }
    for (std::size_t k = 8; k < kGantrySubBytes; k += 8) {
      if (!std::isfinite(get_f64(p + k))) return Status::kTableInvalid;
    }
    StoredSubMachine& s = t.sub_machines[i];
    F64Reader rs{p + 8};
    sub_fields(rs, s);
    if (!valid(s)) return Status::kTableInvalid;
    s.present = true;
    s.master_axis = static_cast<Axis>(p[0]);
    s.sub_T_global = inverse(s.global_T_sub);
  }
  out = t;
  return Status::kOk;
}

}  // namespace trueaxis::core
