#include "gltf/gltf_nodes.h"

#include <cmath>

#include "gltf/gltf_common.h"

namespace partita::gltf {

namespace {

void checkFinite(const std::vector<double>& values, int node, const char* what) {
    for (double v : values)
        if (!std::isfinite(v)) failf("node {}: {} holds a NaN or infinite value", node, what);
}

void checkLength(const std::vector<double>& values, size_t expected, int node, const char* what) {
    if (!values.empty() && values.size() != expected)
        failf("node {}: {} has {} numbers, expected {}", node, what, values.size(), expected);
    checkFinite(values, node, what);
}

Mat4 fromMatrix(const std::vector<double>& values) {
    Mat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m.m[c][r] = toFloat(values[size_t(c * 4 + r)]);
    return m;
}

Vec3f toVec3(const std::vector<double>& v) { return {toFloat(v[0]), toFloat(v[1]), toFloat(v[2])}; }

Mat4 rotationOf(LoadContext& ctx, const std::vector<double>& q, int index) {
    double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(len > 0) || !std::isfinite(len)) {
        ctx.warn(fmt::format("node {}: rotation quaternion has zero length; ignoring it", index));
        return Mat4::identity();
    }
    // Exporters write slightly non-unit quaternions; normalising keeps the rotation orthonormal.
    return Mat4::rotation(float(q[0] / len), float(q[1] / len), float(q[2] / len),
                          float(q[3] / len));
}

std::vector<int> rootNodes(LoadContext& ctx) {
    const tinygltf::Model& model = ctx.model;
    if (model.scenes.empty()) {
        std::vector<bool> hasParent(model.nodes.size());
        for (const tinygltf::Node& node : model.nodes)
            for (int child : node.children)
                if (child >= 0 && size_t(child) < hasParent.size()) hasParent[size_t(child)] = true;
        std::vector<int> roots;
        for (size_t i = 0; i < hasParent.size(); ++i)
            if (!hasParent[i]) roots.push_back(int(i));
        if (!roots.empty()) ctx.warn("file has no scenes; using every root node");
        return roots;
    }
    int scene = model.defaultScene == -1 ? 0 : model.defaultScene;
    if (scene < 0 || size_t(scene) >= model.scenes.size())
        failf("default scene index {} is out of range (the file has {})", scene,
              model.scenes.size());
    return model.scenes[size_t(scene)].nodes;
}

struct PendingNode {
    int node;
    int depth;
    Mat4 parentToWorld;
};

}  // namespace

Mat4 localTransform(LoadContext& ctx, const tinygltf::Node& node, int index) {
    if (!node.matrix.empty()) {
        checkLength(node.matrix, 16, index, "matrix");
        return fromMatrix(node.matrix);
    }
    checkLength(node.translation, 3, index, "translation");
    checkLength(node.rotation, 4, index, "rotation");
    checkLength(node.scale, 3, index, "scale");
    Mat4 m = Mat4::identity();
    if (!node.translation.empty()) m = Mat4::translation(toVec3(node.translation));
    if (!node.rotation.empty()) m = m * rotationOf(ctx, node.rotation, index);
    if (!node.scale.empty()) m = m * Mat4::scale(toVec3(node.scale));
    return m;
}

std::vector<NodeInstance> flattenDefaultScene(LoadContext& ctx) {
    const auto& nodes = ctx.model.nodes;
    std::vector<bool> visited(nodes.size());
    std::vector<NodeInstance> out;
    std::vector<PendingNode> stack;
    std::vector<int> roots = rootNodes(ctx);
    for (auto it = roots.rbegin(); it != roots.rend(); ++it)
        stack.push_back({*it, 1, Mat4::identity()});
    // An explicit stack, and each node at most once: a cyclic or shared ("DAG") hierarchy cannot
    // recurse without end or blow up exponentially.
    while (!stack.empty()) {
        PendingNode pending = stack.back();
        stack.pop_back();
        int index = pending.node;
        const tinygltf::Node& node = checkedAt(nodes, index, "node");
        if (visited[size_t(index)])
            failf(
                "node {} is reached twice: the node hierarchy has a cycle or a node with two "
                "parents",
                index);
        visited[size_t(index)] = true;
        if (pending.depth > ctx.limits.maxNodeDepth)
            failf("node hierarchy is deeper than {} levels (at node {})", ctx.limits.maxNodeDepth,
                  index);
        Mat4 toWorld = pending.parentToWorld * localTransform(ctx, node, index);
        out.push_back({index, toWorld});
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
            stack.push_back({*it, pending.depth + 1, toWorld});
    }
    return out;
}

}  // namespace partita::gltf
