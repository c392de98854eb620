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

// Layout 2's additions (gantry_table.hpp), after layout 1's bytes.
template <typename Io, typename Global>
void global_figure_fields(Io& io, Global& g) {
  io(g.bed_flatness_noise_floor_mm);
  io(g.gantry_straightness_noise_floor_mm);
  io(g.bed_form_error_mm);
  io(g.bed_form_error_sigma_mm);
  io(g.gantry_form_error_mm);
  io(g.gantry_form_error_sigma_mm);
}

template <typename Io, typename Sub>
void sub_figure_fields(Io& io, Sub& s) {
  io(s.squareness_sigma_arcsec);
  io(s.a_c_offset_sigma_mm);
  io(s.a_c_angle_sigma_deg);
}

bool rotation(const Mat3& r) {
  return (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() <= kGantryRotationTolerance &&
         std::abs(r.determinant() - 1.0) <= kGantryRotationTolerance;
}

bool nonnegative(const Vec3& v) { return v.minCoeff() >= 0.0; }

// A layout-2 figure: >= 0, or not stored (convention 4).
bool figure(double x) { return x >= 0.0 || x == kFigureNotStored; }
bool figure(const Vec3& v) { return figure(v.x()) && figure(v.y()) && figure(v.z()); }

bool figures_valid(const StoredGlobal& g) {
  return figure(g.bed_flatness_noise_floor_mm) && figure(g.gantry_straightness_noise_floor_mm) &&
         figure(g.bed_form_error_mm) && figure(g.bed_form_error_sigma_mm) && figure(g.gantry_form_error_mm) &&
         figure(g.gantry_form_error_sigma_mm);
}

bool figures_valid(const StoredSubMachine& s) {
  return figure(s.squareness_sigma_arcsec) && figure(s.a_c_offset_sigma_mm) && figure(s.a_c_angle_sigma_deg);
}

void not_stored(StoredGlobal& g) {
  g.bed_flatness_noise_floor_mm = g.gantry_straightness_noise_floor_mm = kFigureNotStored;
  g.bed_form_error_mm = g.bed_form_error_sigma_mm = kFigureNotStored;
  g.gantry_form_error_mm = g.gantry_form_error_sigma_mm = kFigureNotStored;
}

void not_stored(StoredSubMachine& s) {
  s.squareness_sigma_arcsec = Vec3::Constant(kFigureNotStored);
  s.a_c_offset_sigma_mm = s.a_c_angle_sigma_deg = kFigureNotStored;
}

bool all_finite(const std::uint8_t* p, std::size_t bytes) {
  for (std::size_t k = 0; k < bytes; k += 8) {
    if (!std::isfinite(get_f64(p + k))) return false;
  }
  return true;
}

bool all_zero(const std::uint8_t* p, std::size_t bytes) {
  for (std::size_t k = 0; k < bytes; ++k) {
    if (p[k] != 0) return false;
  }
  return true;
}

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
std::uint8_t* sub_figure_bytes(std::uint8_t* out, std::size_t i) {
  return out + kGantryTableBytesV1 + kGantryGlobalFigureBytes + i * kGantrySubFigureBytes;
}
const std::uint8_t* sub_figure_bytes(const std::uint8_t* in, std::size_t i) {
  return in + kGantryTableBytesV1 + kGantryGlobalFigureBytes + i * kGantrySubFigureBytes;
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
  g.bed_flatness_noise_floor_mm = global.bed_flatness_noise_floor_mm;
  g.gantry_straightness_noise_floor_mm = global.gantry_straightness_noise_floor_mm;
  g.bed_form_error_mm = global.bed_form_error_mm;
  g.bed_form_error_sigma_mm = global.bed_form_error_sigma_mm;
  g.gantry_form_error_mm = global.gantry_form_error_mm;
  g.gantry_form_error_sigma_mm = global.gantry_form_error_sigma_mm;
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
  s.squareness_sigma_arcsec = f.squareness_sigma_arcsec;
  s.a_c_offset_sigma_mm = f.a_c_offset_sigma_mm;
  s.a_c_angle_sigma_deg = f.a_c_angle_sigma_deg;
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
  F64Writer wf{out + kGantryTableBytesV1};
  global_figure_fields(wf, g);
  for (std::size_t i = 0; i < kMaxSubMachines; ++i) {
    StoredSubMachine s = table.sub_machines[i];
    if (!s.present) continue;
    std::uint8_t* p = sub_bytes(out, i);
    p[0] = static_cast<std::uint8_t>(s.master_axis);
    F64Writer ws{p + 8};
    sub_fields(ws, s);
    F64Writer wsf{sub_figure_bytes(out, i)};
    sub_figure_fields(wsf, s);
  }
  return kGantryTableBytes;
}

namespace {

// Decodes the global frame, or sub-machine i (present in the mask), of a table
// whose size and header passed; false when a value fails its check.
bool read_global(const std::uint8_t* bytes, bool layout_2, StoredGlobal& g) {
  if (!all_finite(bytes + kGantryHeaderBytes, kGantryGlobalBytes)) return false;
  if (layout_2 && !all_finite(bytes + kGantryTableBytesV1, kGantryGlobalFigureBytes)) return false;
  F64Reader r{bytes + kGantryHeaderBytes};
  global_fields(r, g);
  if (layout_2) {
    F64Reader rf{bytes + kGantryTableBytesV1};
    global_figure_fields(rf, g);
  } else {
    not_stored(g);
  }
  return valid(g) && figures_valid(g);
}

bool read_sub(const std::uint8_t* bytes, bool layout_2, std::size_t i, StoredSubMachine& s) {
  const std::uint8_t* p = sub_bytes(bytes, i);
  const std::uint8_t* pf = layout_2 ? sub_figure_bytes(bytes, i) : nullptr;
  if (p[0] > 2 || !all_zero(p + 1, 7) || !all_finite(p + 8, kGantrySubBytes - 8)) return false;
  if (layout_2 && !all_finite(pf, kGantrySubFigureBytes)) return false;
  F64Reader rs{p + 8};
  sub_fields(rs, s);
  if (layout_2) {
    F64Reader rsf{pf};
    sub_figure_fields(rsf, s);
  } else {
    not_stored(s);
  }
  if (!valid(s) || !figures_valid(s)) return false;
  s.present = true;
  s.master_axis = static_cast<Axis>(p[0]);
  s.sub_T_global = inverse(s.global_T_sub);
  return true;
}

bool absent_zero(const std::uint8_t* bytes, bool layout_2, std::size_t i) {
  return all_zero(sub_bytes(bytes, i), kGantrySubBytes) &&
         (!layout_2 || all_zero(sub_figure_bytes(bytes, i), kGantrySubFigureBytes));
}

}  // namespace

Status decode_gantry_table(const std::uint8_t* bytes, std::size_t size, GantryTable& out) {
  if (bytes == nullptr || (size != kGantryTableBytes && size != kGantryTableBytesV1)) return Status::kTableInvalid;
  const bool layout_2 = size == kGantryTableBytes;
  const std::uint16_t mask = get_u16(bytes + 2);
  if (get_u16(bytes) != (layout_2 ? kGantryLayoutVersion : 1) || mask == 0 || mask >= (1u << kMaxSubMachines) ||
      get_u32(bytes + 4) != 0) {
    return Status::kTableInvalid;
  }
  // Every value is checked before `out` is touched; one frame at a time, not a
  // whole table on the stack (Module::start() decodes within its stack bound).
  StoredGlobal g;
  if (!read_global(bytes, layout_2, g)) return Status::kTableInvalid;
  StoredSubMachine s;
  for (std::size_t i = 0; i < kMaxSubMachines; ++i) {
    const bool ok = (mask & (1u << i)) != 0 ? read_sub(bytes, layout_2, i, s) : absent_zero(bytes, layout_2, i);
    if (!ok) return Status::kTableInvalid;
  }
  out.global = g;
  for (std::size_t i = 0; i < kMaxSubMachines; ++i) {
    out.sub_machines[i] = StoredSubMachine();
    if ((mask & (1u << i)) != 0) static_cast<void>(read_sub(bytes, layout_2, i, out.sub_machines[i]));
  }
  return Status::kOk;
}

}  // namespace trueaxis::core
