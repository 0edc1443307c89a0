// OBJ export of posed scenes.
#include "coordinator/export/obj_export.h"

#include <algorithm>
#include <cstdio>
#include <memory>

#include <fmt/format.h>

#include "common/math/transform.h"

namespace pathfarm::coord {
namespace {

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

std::vector<int> nodes_in_source_order(const SceneModel& scene) {
    std::vector<int> order(scene.nodes.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = int(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        const int sa = scene.nodes[a].source_index, sb = scene.nodes[b].source_index;
        if ((sa < 0) != (sb < 0)) return sb < 0;  // nodes from a file first
        return sa < sb;
    });
    return order;
}

}  // namespace

Status export_posed_obj(const SceneModel& posed, const std::string& path) {
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "w"));
    if (!file) return make_error(ErrorCode::io_error, "{}: cannot open for writing", path);
    std::vector<std::vector<int>> node_instances(posed.nodes.size());
    for (std::size_t i = 0; i < posed.instances.size(); ++i)
        node_instances[posed.instances[i].node].push_back(int(i));
    fmt::print(file.get(), "# pathfarm posed scene: {}\n", posed.name);
    std::size_t base = 1;  // OBJ indices are 1-based and global
    for (int n : nodes_in_source_order(posed)) {
        if (node_instances[n].empty()) continue;
        const Node& node = posed.nodes[n];
        fmt::print(file.get(), "o {}\n",
                   node.name.empty()
                       ? fmt::format("node{}", node.source_index >= 0 ? node.source_index : n)
                       : node.name);
        for (int i : node_instances[n]) {
            const Instance& inst = posed.instances[i];
            const Mesh& mesh = posed.meshes[inst.mesh];
            for (const Vec3& p : mesh.positions) {
                const Vec3 w = transform_point(inst.transform, p);
                fmt::print(file.get(), "v {:.9g} {:.9g} {:.9g}\n", w.x, w.y, w.z);
            }
            for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
                fmt::print(file.get(), "f {} {} {}\n", base + mesh.indices[t],
                           base + mesh.indices[t + 1], base + mesh.indices[t + 2]);
            base += mesh.positions.size();
        }
    }
    if (std::ferror(file.get())) return make_error(ErrorCode::io_error, "{}: write failed", path);
    return {};
}

}  // namespace pathfarm::coord
