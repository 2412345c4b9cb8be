// Animated glTF meshes at rest: morph targets at their default weights and skins at the pose
// their joints' node transforms give (no animation is evaluated), so that an animated file
// renders the still pose its author saved.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "renderer/scene_description.h"

namespace prism::gltf_detail {

// What makes one placement of a mesh differ from another: its morph weights and its skin.
struct RestPose {
  std::vector<double> weights;       // one per morph target; empty = no targets applied
  std::vector<M44d> joint_matrices;  // inverseBind_j * world(joint_j); empty = not skinned
};

// node.weights if the node has them, else mesh.weights, else zeros; their count must equal the
// number of morph targets of each primitive of the mesh. Empty when the mesh has no targets or
// every weight is 0 (nothing to apply).
std::vector<double> morph_weights(const tinygltf::Model& model, const tinygltf::Node& node,
                                  const std::string& node_element, const std::string& file);

// The joint matrices of skin `skin` for linear-blend skinning, in Imath's row-vector convention:
// p_world = p_object * inverseBindMatrix_j * world(joint_j). `world` gives a node's world
// matrix (it throws for a node outside the node forest).
std::vector<M44d> joint_matrices(const tinygltf::Model& model, int skin,
                                 const std::function<M44d(int node)>& world,
                                 const std::string& file);

// Applies the morph targets, then the skin, to `out` (converted from `in`): positions, normals
// and tangents (renormalised; tangents the loader generated follow the base mesh). A skinned
// primitive ends up in world space. Validates the targets' POSITION/NORMAL accessors (FLOAT VEC3,
// one per vertex, finite results) and JOINTS_n/WEIGHTS_n (one per vertex, joint indices below the
// skin's joint count, weights finite and >= 0).
void pose_primitive(const tinygltf::Model& model, const tinygltf::Primitive& in,
                    const RestPose& pose, const std::string& element, const std::string& file,
                    Primitive& out, std::vector<std::string>& warnings);

}  // namespace prism::gltf_detail
