#include "scene_io/gltf_rest_pose.h"

#include <array>
#include <cmath>

#include "renderer/math.h"
#include "scene_io/gltf_accessors.h"
#include "scene_io/gltf_budget.h"
#include "scene_io/gltf_error.h"

namespace prism::gltf_detail {

namespace {

bool finite(const V3d& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check_weights(const std::vector<double>& weights, const std::string& element,
                   const std::string& file) {
  for (std::size_t i = 0; i < weights.size(); ++i) {
    if (!std::isfinite(weights[i])) fail(file, indexed(element, i), "weight is not finite");
  }
}

void apply_morph_targets(const tinygltf::Model& model, const tinygltf::Primitive& in,
                         const std::vector<double>& weights, const std::string& element,
                         const std::string& file, Primitive& out) {
  const std::size_t vertices = out.positions.size();
  // Summed in double: many small targets must not lose what float would round away.
  charge(vertices, 3 * sizeof(V3d), element + ".targets");
  std::vector<V3d> positions(out.positions.begin(), out.positions.end());
  std::vector<V3d> normals(out.normals.begin(), out.normals.end());
  std::vector<V3d> tangents;
  for (const Imath::V4f& t : out.tangents) tangents.emplace_back(t.x, t.y, t.z);
  bool moved_normals = false;
  bool moved_tangents = false;
  for (std::size_t t = 0; t < in.targets.size(); ++t) {
    const double w = weights[t];
    if (w == 0.0) continue;
    const std::string target_element = indexed(element + ".targets", t);
    for (const auto& [name, accessor] : in.targets[t]) {
      const bool is_position = name == "POSITION";
      const bool is_normal = name == "NORMAL";
      if (!is_position && !is_normal && name != "TANGENT") continue;  // not used by the renderer
      std::vector<V3d>& values = is_position ? positions : is_normal ? normals : tangents;
      if (values.empty()) continue;  // dropped or absent (generated tangents follow the base)
      const std::string attr_element = target_element + "." + name;
      const AccessorView view = view_accessor(model, accessor, attr_element, file);
      if (view.count != vertices) {
        fail(file, attr_element,
             name + " has " + std::to_string(view.count) + " elements but POSITION has " +
                 std::to_string(vertices));
      }
      const std::vector<V3f> deltas = read_vec3_float(view, "morph target " + name, file);
      for (std::size_t i = 0; i < vertices; ++i) values[i] += w * V3d(deltas[i]);
      moved_normals = moved_normals || is_normal;
      moved_tangents = moved_tangents || (!is_position && !is_normal);
    }
  }
  for (std::size_t i = 0; i < vertices; ++i) {
    if (!finite(positions[i])) {
      fail(file, element + ".targets",
           "vertex " + std::to_string(i) + " is not finite after the morph targets");
    }
    out.positions[i] = V3f(positions[i]);
  }
  if (moved_normals) {
    for (std::size_t i = 0; i < vertices; ++i) {
      const double length = normals[i].length();
      if (!(length > 0.0) || !std::isfinite(length)) {
        fail(file, element + ".targets",
             "normal " + std::to_string(i) + " is zero or not finite after the morph targets");
      }
      out.normals[i] = V3f(normals[i] / length);
    }
  }
  if (moved_tangents) {
    for (std::size_t i = 0; i < vertices; ++i) {
      const double length = tangents[i].length();
      if (!(length > 0.0) || !std::isfinite(length)) {
        fail(file, element + ".targets",
             "tangent " + std::to_string(i) + " is zero or not finite after the morph targets");
      }
      const V3d t = tangents[i] / length;
      out.tangents[i] = Imath::V4f(float(t.x), float(t.y), float(t.z), out.tangents[i].w);
    }
  }
}

void apply_skin(const tinygltf::Model& model, const tinygltf::Primitive& in,
                const std::vector<M44d>& joints, const std::string& element,
                const std::string& file, Primitive& out, std::vector<std::string>& warnings) {
  const std::size_t vertices = out.positions.size();
  charge(vertices, sizeof(M44d) + sizeof(double), element + ".attributes.JOINTS_0");
  std::vector<M44d> blended(vertices, M44d(0.0));
  std::vector<double> total(vertices, 0.0);
  int sets = 0;
  for (;; ++sets) {
    const std::string joints_name = "JOINTS_" + std::to_string(sets);
    const std::string weights_name = "WEIGHTS_" + std::to_string(sets);
    const auto j = in.attributes.find(joints_name);
    const auto w = in.attributes.find(weights_name);
    if (j == in.attributes.end() && w == in.attributes.end()) break;
    if (j == in.attributes.end() || w == in.attributes.end()) {
      fail(file, element + ".attributes",
           (j == in.attributes.end() ? weights_name + " without " + joints_name
                                     : joints_name + " without " + weights_name));
    }
    const std::string j_element = element + ".attributes." + joints_name;
    const std::string w_element = element + ".attributes." + weights_name;
    const AccessorView j_view = view_accessor(model, j->second, j_element, file);
    const AccessorView w_view = view_accessor(model, w->second, w_element, file);
    for (const auto* v : {&j_view, &w_view}) {
      if (v->count != vertices) {
        fail(file, v == &j_view ? j_element : w_element,
             std::to_string(v->count) + " elements but POSITION has " + std::to_string(vertices));
      }
    }
    const auto indices = read_joints(j_view, joints_name, file);
    const auto weights = read_weights(w_view, weights_name, file);
    for (std::size_t i = 0; i < vertices; ++i) {
      for (int c = 0; c < 4; ++c) {
        const double weight = weights[i][c];
        if (!std::isfinite(weight) || weight < 0.0) {
          fail(file, w_view.element(),
               "weight " + std::to_string(weight) + " of vertex " + std::to_string(i) +
                   " is negative or not finite");
        }
        // glTF requires every joint index to be valid, weighted or not.
        if (indices[i][c] >= joints.size()) {
          fail(file, j_view.element(),
               "joint " + std::to_string(indices[i][c]) + " of vertex " + std::to_string(i) +
                   " out of range (the skin has " + std::to_string(joints.size()) + " joints)");
        }
        if (weight == 0.0) continue;
        blended[i] += joints[indices[i][c]] * weight;
        total[i] += weight;
      }
    }
  }
  if (sets == 0) {
    fail(file, element + ".attributes", "the node has a skin but the primitive has no JOINTS_0");
  }
  std::size_t unweighted = 0;
  for (std::size_t i = 0; i < vertices; ++i) {
    // Exporters round weights (often to 8 bits); glTF says they sum to 1, so renormalise.
    M44d m = total[i] > 0.0 ? blended[i] * (1.0 / total[i]) : M44d();
    if (total[i] <= 0.0) ++unweighted;
    const V3d p = V3d(out.positions[i]) * m;
    if (!finite(p)) {
      fail(file, element, "skinned vertex " + std::to_string(i) + " is not finite");
    }
    out.positions[i] = V3f(p);
    const Imath::M33d linear(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1],
                             m[2][2]);
    if (!out.tangents.empty()) {
      // Tangents are directions on the surface: they move with it. A mirroring blend flips the
      // bitangent's side, so w flips with it.
      Imath::V4f& t = out.tangents[i];
      const V3d d = V3d(t.x, t.y, t.z) * linear;
      const double length = d.length();
      if (!(length > 0.0) || !std::isfinite(length)) {
        fail(file, element, "skinned tangent " + std::to_string(i) + " is zero or not finite");
      }
      const float w = linear.determinant() < 0.0 ? -t.w : t.w;
      t = Imath::V4f(float(d.x / length), float(d.y / length), float(d.z / length), w);
    }
    if (!out.normals.empty()) {
      // Normals go through the inverse transpose of the blended linear part.
      const Imath::M33d normal_matrix = linear.inverse().transposed();
      const V3d n = V3d(out.normals[i]) * normal_matrix;
      const double length = n.length();
      if (!(length > 0.0) || !std::isfinite(length)) {
        fail(file, element, "skinned normal " + std::to_string(i) + " is zero or not finite");
      }
      out.normals[i] = V3f(n / length);
    }
  }
  if (unweighted > 0) {
    warnings.push_back(warning(element, std::to_string(unweighted) +
                                            " vertices have no joint weight; they stay where the "
                                            "skin's space puts them unskinned"));
  }
}

}  // namespace

std::vector<double> morph_weights(const tinygltf::Model& model, const tinygltf::Node& node,
                                  const std::string& node_element, const std::string& file) {
  const tinygltf::Mesh& mesh = model.meshes[static_cast<std::size_t>(node.mesh)];
  const std::string mesh_element = indexed("meshes", static_cast<std::size_t>(node.mesh));
  const std::size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    if (mesh.primitives[p].targets.size() != targets) {
      fail(file, indexed(mesh_element + ".primitives", p) + ".targets",
           std::to_string(mesh.primitives[p].targets.size()) +
               " morph targets, but primitives[0] has " + std::to_string(targets) +
               " (glTF requires the same number)");
    }
  }
  const bool from_node = !node.weights.empty();
  const std::vector<double>& weights = from_node ? node.weights : mesh.weights;
  const std::string element = from_node ? node_element + ".weights" : mesh_element + ".weights";
  if (!weights.empty() && weights.size() != targets) {
    fail(file, element,
         std::to_string(weights.size()) + " weights for " + std::to_string(targets) +
             " morph targets");
  }
  check_weights(weights, element, file);
  for (double w : weights) {
    if (w != 0.0) return weights;
  }
  return {};
}

std::vector<M44d> joint_matrices(const tinygltf::Model& model, int skin,
                                 const std::function<M44d(int node)>& world,
                                 const std::string& file) {
  const tinygltf::Skin& s = model.skins[static_cast<std::size_t>(skin)];
  const std::string element = indexed("skins", static_cast<std::size_t>(skin));
  if (s.joints.empty()) fail(file, element + ".joints", "a skin needs at least one joint");
  charge(s.joints.size(), 2 * sizeof(M44d), element + ".joints");
  std::vector<M44d> inverse_bind(s.joints.size(), M44d());
  if (s.inverseBindMatrices >= 0) {
    const AccessorView view =
        view_accessor(model, s.inverseBindMatrices, element + ".inverseBindMatrices", file);
    if (view.count < s.joints.size()) {
      fail(file, element + ".inverseBindMatrices",
           std::to_string(view.count) + " matrices for " + std::to_string(s.joints.size()) +
               " joints");
    }
    inverse_bind = read_mat4_float(view, "inverseBindMatrices", file);
    inverse_bind.resize(s.joints.size());
  }
  std::vector<M44d> out(s.joints.size());
  for (std::size_t j = 0; j < s.joints.size(); ++j) {
    const int node = s.joints[j];
    if (node < 0 || static_cast<std::size_t>(node) >= model.nodes.size()) {
      fail(file, indexed(element + ".joints", j),
           "node " + std::to_string(node) + " out of range (" + std::to_string(model.nodes.size()) +
               " nodes)");
    }
    out[j] = inverse_bind[j] * world(node);
    if (!is_finite(out[j])) fail(file, indexed(element + ".joints", j), "joint matrix not finite");
  }
  return out;
}

void pose_primitive(const tinygltf::Model& model, const tinygltf::Primitive& in,
                    const RestPose& pose, const std::string& element, const std::string& file,
                    Primitive& out, std::vector<std::string>& warnings) {
  if (!pose.weights.empty()) apply_morph_targets(model, in, pose.weights, element, file, out);
  if (!pose.joint_matrices.empty()) {
    apply_skin(model, in, pose.joint_matrices, element, file, out, warnings);
  }
}

}  // namespace prism::gltf_detail
