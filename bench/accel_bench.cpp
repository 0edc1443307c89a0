// BVH maintenance benchmark (issue: coordinator core). Prints CSV rows
// `measure,triangles_or_instances,median_ms,per_1000_ms` to stdout:
//   build of the Stanford dragon (871k triangles), refit and rebuild per 1000 dynamic
//   triangles, top-level rebuild for 1k and 10k instances, and the per-frame update of a large
//   static scene plus one skinned model next to that skinned model alone; and the tracers'
//   closed-surface analysis for light culling (SealedEmitters) on Sponza and two built-ins;
//   the light tree over builtin:light-field's 9 892 emitters: build, refit after its ring
//   turned, and the whole light sampler built or refitted (issue: many lights).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "bench/bench_usage.h"
#include "common/base/log.h"
#include "common/base/timer.h"
#include "common/render/light_sampler.h"
#include "common/render/sealed_emitters.h"
#include "common/sampling/rng.h"
#include "common/scene/load/builtin_scenes.h"
#include "common/scene/load/procedural_mesh.h"
#include "common/scene/load/scene_loader.h"
#include "coordinator/accel/accel_updater.h"
#include "coordinator/scene_graph/scene_graph.h"

using namespace pathfarm;
using namespace pathfarm::coord;

namespace {

template <typename F>
double median_ms(int runs, F&& f) {
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
        const Timer timer;
        f();
        t.push_back(timer.milliseconds());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

void row(const char* what, std::size_t n, double ms) {
    std::printf("%s,%zu,%.3f,%.4f\n", what, n, ms, ms / (double(n) / 1000.0));
}

SceneModel merge(SceneModel a, const SceneModel& b) {  // b's nodes, meshes and clips appended
    const int meshes = int(a.meshes.size()), materials = int(a.materials.size()),
              nodes = int(a.nodes.size());
    const int textures = int(a.textures.size()), images = int(a.images.size()),
              skins = int(a.skins.size());
    for (Image img : b.images)
        a.images.push_back(std::move(img));
    for (Texture t : b.textures) {
        if (t.image >= 0) t.image += images;
        a.textures.push_back(t);
    }
    for (Material m : b.materials) {
        for (TextureRef* r : {&m.base_color_texture, &m.metallic_roughness_texture,
                              &m.normal_texture, &m.emissive_texture})
            if (r->texture >= 0) r->texture += textures;
        a.materials.push_back(std::move(m));
    }
    for (Mesh m : b.meshes) {
        m.material += materials;
        a.meshes.push_back(std::move(m));
    }
    for (Node n : b.nodes) {
        if (n.parent >= 0) n.parent += nodes;
        for (int& m : n.meshes)
            m += meshes;
        if (n.skin >= 0) n.skin += skins;
        n.camera = -1;
        a.nodes.push_back(std::move(n));
    }
    for (Skin s : b.skins) {
        for (int& j : s.joints)
            j += nodes;
        a.skins.push_back(std::move(s));
    }
    for (AnimationClip c : b.animations) {
        for (AnimationChannel& ch : c.channels)
            ch.node += nodes;
        a.animations.push_back(std::move(c));
    }
    flatten_nodes(a);
    return a;
}

double mean_update_ms(SceneModel scene, int frames) {
    SceneGraph graph(std::move(scene));
    graph.set_playing_clip(int(0));
    AccelUpdater accel;
    accel.build(graph.state(), 0);
    double total = 0.0;
    for (int f = 1; f <= frames; ++f) {
        graph.advance(f / 30.0);
        const ChangeSet c = graph.take_changes();
        const Timer timer;
        accel.update(graph.state(), c, uint64_t(f));
        total += timer.milliseconds();
    }
    return total / frames;
}

// Build, refit and rebuild of the dragon's BVH; top-level builds over random instance boxes.
void bvh_rows(Mesh d) {
    const std::size_t tris = d.triangle_count();
    Bvh bvh;
    row("build_dragon", tris, median_ms(3, [&] { bvh = build_bvh(d.positions, d.indices); }));
    Pcg32 rng(1);
    for (Vec3& p : d.positions)
        p += 1e-4f * Vec3(rng.next_float(), rng.next_float(), rng.next_float());
    row("refit_dragon", tris, median_ms(5, [&] { refit_bvh(bvh, d.positions, d.indices); }));
    row("rebuild_dragon", tris, median_ms(3, [&] { bvh = build_bvh(d.positions, d.indices); }));
    for (int n : {1000, 10000}) {
        std::vector<Bounds3f> boxes(static_cast<std::size_t>(n));
        for (Bounds3f& b : boxes) {
            const Vec3 c(rng.next_float() * 100, rng.next_float() * 10, rng.next_float() * 100);
            b = Bounds3f{c - Vec3(0.5f), c + Vec3(0.5f)};
        }
        row(n == 1000 ? "top_level_1k_instances" : "top_level_10k_instances", std::size_t(n),
            median_ms(5, [&] { bvh = build_bvh(boxes); }));
    }
}

// The closed-surface analysis from scratch, and adopted after a camera move (in a tracer the
// whole scene is translated by the recentring).
void sealed_emitter_rows(const SceneModel& sponza) {
    const std::pair<const char*, SceneModel> cases[] = {
        {"sealed_emitters_sponza", sponza},
        {"sealed_emitters_default", make_default_scene()},
        {"sealed_emitters_sealed_lights", make_sealed_lights_scene()}};
    for (const auto& [name, model] : cases)
        row(name, triangle_count(model), median_ms(5, [&] { const SealedEmitters sealed(model); }));
    SealedEmitters sealed(sponza);
    SceneModel moved = sponza;
    for (Instance& inst : moved.instances)
        inst.transform = glm::translate(Mat4(1.0f), Vec3(0.1f, 0.0f, 0.2f)) * inst.transform;
    row("sealed_emitters_adopt_translated_sponza", triangle_count(sponza),
        median_ms(5, [&] { (void)sealed.adopt_translated(moved); }));
    // A deforming occluder in a level (a skinned figure's stand-in: a sphere whose vertices
    // move every frame, floating in Sponza's court): adopted, its surfaces welded again alone,
    // against analysed from scratch.
    SceneModel level = sponza;
    level.meshes.push_back(make_sphere(0.5f, 24, 48, 0));
    const std::size_t sphere = level.meshes.size() - 1;
    level.instances.push_back(
        {int(sphere), -1, glm::translate(Mat4(1.0f), Vec3(0.0f, 3.0f, 0.0f)), 0, true});
    const std::vector<Vec3> rest = level.meshes[sphere].positions;
    int frame = 0, adopted = 0;
    const auto deform = [&] {
        const float s = 1.0f + 0.01f * float(++frame % 7);
        for (std::size_t v = 0; v < rest.size(); ++v)
            level.meshes[sphere].positions[v] = rest[v] * Vec3(s, 1.0f, 1.0f / s);
    };
    auto kept = std::make_unique<SealedEmitters>(level);
    row("sealed_emitters_deformed_sphere_in_sponza_adopted", triangle_count(level),
        median_ms(5, [&] {
            deform();
            if (kept->adopt(level))
                ++adopted;
            else
                kept = std::make_unique<SealedEmitters>(level);
        }));
    row("sealed_emitters_deformed_sphere_in_sponza_analysed", triangle_count(level),
        median_ms(5, [&] {
            deform();
            const SealedEmitters fresh(level);
        }));
    std::fprintf(stderr, "accel_bench: the deformed sphere was adopted %d times of 5\n", adopted);
}

// The light tree over builtin:light-field's emitters: built, refitted after the ring turned
// by a frame's angle, and the light sampler (emitter list, power, tree) built from nothing or
// with its meshes' topologies kept from the last state (what the tracers do).
void light_tree_rows() {
    const SceneModel field = make_light_field_scene();
    SceneModel turned = field;
    for (Instance& inst : turned.instances)
        if (field.nodes[std::size_t(inst.node)].name == "ring")
            inst.transform = glm::rotate(Mat4(1.0f), 0.05f, Vec3(0, 1, 0)) * inst.transform;
    const auto bounds_of = [](const LightSampler& s) {
        std::vector<LightBounds> b;
        for (const auto& t : s.triangles())
            b.push_back(triangle_light_bounds(t.p0, t.p0 + t.e1, t.p0 + t.e2, t.n, t.area, false));
        return b;
    };
    const ShadingScene shading(field), shading_turned(turned);
    const std::vector<LightBounds> before = bounds_of(LightSampler(shading)),
                                   after = bounds_of(LightSampler(shading_turned));
    LightTree tree(before);
    row("light_tree_build_light_field", before.size(),
        median_ms(9, [&] { tree = LightTree(before); }));
    row("light_tree_refit_light_field", after.size(), median_ms(9, [&] {
                                                          tree.refit(after);
                                                          tree.refit(before);
                                                      }) / 2.0);
    row("light_sampler_tree_light_field", before.size(),
        median_ms(9, [&] { const LightSampler s(shading, {}, LightSelection::tree); }));
    // What a tracer pays per state once its meshes' topologies are kept (light_topology.h):
    // the emitter list, the clusters refitted and a top level built over them.
    LightTopologyCache cache;
    const LightSampler warm(shading, {}, LightSelection::tree, &cache);
    const std::size_t builds = cache.builds();
    row("light_sampler_tree_kept_topology_light_field", before.size(), median_ms(9, [&] {
            const LightSampler s(shading_turned, {}, LightSelection::tree, &cache);
        }));
    if (cache.builds() != builds) std::fprintf(stderr, "accel_bench: a mesh tree was rebuilt\n");
    // --light-sampler auto on top of that: the same tree, then its reading (it keeps the tree).
    row("light_sampler_auto_kept_topology_light_field", before.size(), median_ms(9, [&] {
            const LightSampler s(shading_turned, {}, LightSelection::automatic, &cache);
        }));
    // The demo's scene, whose light sampler a tracer builds anew each frame.
    const SceneModel game = make_default_scene();
    const ShadingScene shading_game(game);
    for (LightSelection s : {LightSelection::tree, LightSelection::automatic})
        row(s == LightSelection::tree ? "light_sampler_tree_default" : "light_sampler_auto_default",
            LightSampler(shading_game).triangle_count(),
            median_ms(9, [&] { const LightSampler l(shading_game, {}, s); }));
}

Result<SceneModel> load_or_report(const std::string& path) {
    auto scene = load_scene(path);
    if (!scene) std::fprintf(stderr, "accel_bench: %s\n", scene.error().message.c_str());
    return scene;
}

}  // namespace

int main(int argc, char** argv) {
    init_logging("pathfarm-accel-bench", "error");  // logs go to stderr; stdout is the CSV
    if (int code = bench::usage_exit(
            argc, argv, argc <= 2,
            "usage: pathfarm-accel-bench [SCENES_DIR]\nPrints CSV (measure, count, "
            "median_ms, per_1000_ms): BVH build and refit, skinned updates, sealed-emitter "
            "analysis and the light tree. SCENES_DIR: ../shared/scenes.\n");
        code >= 0)
        return code;
    const std::string scenes = argc > 1 ? argv[1] : "../shared/scenes";
    auto dragon = load_or_report(scenes + "/stanford-dragon/dragon_vrip.ply.gz");
    auto man = load_or_report(scenes + "/cesium-man/CesiumMan.gltf");
    auto sponza = load_or_report(scenes + "/dabrovic-sponza/sponza.obj");
    if (!dragon || !man || !sponza) return 1;
    std::printf("measure,count,median_ms,per_1000_ms\n");
    bvh_rows(dragon->meshes[0]);
    const double alone = mean_update_ms(*man, 30);
    const double with_static = mean_update_ms(merge(*dragon, *man), 30);
    row("update_skinned_alone", triangle_count(*man), alone);
    row("update_skinned_plus_static_dragon", triangle_count(*man) + triangle_count(*dragon),
        with_static);
    sealed_emitter_rows(*sponza);
    light_tree_rows();
    return 0;
}
