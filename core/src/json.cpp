#include "fabkit/core/json.h"

#include <cmath>

namespace fabkit {

double tidy(double v) {
  const double r = std::round(v * 1e6) / 1e6;
  return r == 0 ? 0.0 : r;
}

Json to_json(const Vec3& v) {
  return Json::array({tidy(v.x()), tidy(v.y()), tidy(v.z())});
}

Json to_json(const Frame& f) {
  Frame n = f.normalized();
  // Rounding can carry 359.9999999 up to 360: keep angles in [0, 360).
  for (int i = 0; i < 3; ++i) {
    if (tidy(n.rot[i]) >= 360.0) n.rot[i] -= 360.0;
  }
  return Json{{"pos", to_json(n.pos)}, {"rot", to_json(n.rot)}};
}

Json to_json(const TriangleMesh& m) {
  Json v = Json::array();
  for (const Vec3& x : m.vertices) {
    v.push_back(x.x());
    v.push_back(x.y());
    v.push_back(x.z());
  }
  Json f = Json::array();
  for (const auto& t : m.faces) {
    f.push_back(t[0]);
    f.push_back(t[1]);
    f.push_back(t[2]);
  }
  return Json{{"vertices", std::move(v)}, {"faces", std::move(f)}};
}

Json to_json(const Diagnostic& d) {
  Json j = {{"severity", std::string(to_string(d.severity))},
            {"code", std::string(d.code.name)},
            {"class", std::string(to_string(d.kind()))},
            {"message", d.message}};
  if (d.where.line > 0) j["line"] = d.where.line;
  if (d.where.column > 0) j["column"] = d.where.column;
  j["text"] = d.format();
  return j;
}

Json to_json(const Diagnostics& ds) {
  Json out = Json::array();
  for (const Diagnostic& d : ds) out.push_back(to_json(d));
  return out;
}

std::string dump_json(const Json& j, int indent) {
  return j.dump(indent, ' ', false, Json::error_handler_t::replace);
}

}  // namespace fabkit
