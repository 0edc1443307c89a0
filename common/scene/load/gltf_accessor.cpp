// glTF accessor decoding.
#include "common/scene/load/gltf_accessor.h"

#include <cstring>

#include <tiny_gltf.h>

namespace pathfarm {
namespace {

constexpr std::size_t kMaxAccessorElements = std::size_t(1) << 26;

double read_component(const unsigned char* p, int component_type, bool normalized) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float f;
            std::memcpy(&f, p, 4);
            return f;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return normalized ? *p / 255.0 : *p;
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const auto v = static_cast<int8_t>(*p);
            return normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? v / 65535.0 : v;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
        default:
            return 0.0;
    }
}

// Locates `count` elements of `elem_bytes` in a buffer view, checking they lie inside it.
Result<const unsigned char*> view_data(const tinygltf::Model& model, int view, std::size_t offset,
                                       std::size_t count, std::size_t stride,
                                       std::size_t elem_bytes, int accessor) {
    if (view < 0 || view >= int(model.bufferViews.size()))
        return make_error(ErrorCode::parse_error, "accessor {}: bufferView {} out of range",
                          accessor, view);
    const tinygltf::BufferView& bv = model.bufferViews[view];
    if (bv.buffer < 0 || bv.buffer >= int(model.buffers.size()))
        return make_error(ErrorCode::parse_error, "bufferView {}: buffer {} out of range", view,
                          bv.buffer);
    const auto& data = model.buffers[bv.buffer].data;
    // Every size comes from the file: compared without sums or products that could wrap.
    const bool view_fits =
        bv.byteOffset <= data.size() && bv.byteLength <= data.size() - bv.byteOffset;
    const bool fits =
        view_fits &&
        (count == 0 ||
         (offset <= bv.byteLength && elem_bytes <= bv.byteLength - offset &&
          (count - 1) <= (bv.byteLength - offset - elem_bytes) / std::max<std::size_t>(stride, 1)));
    if (!fits)
        return make_error(ErrorCode::parse_error,
                          "accessor {}: data runs past the end of its buffer (truncated file?)",
                          accessor);
    return data.data() + bv.byteOffset + offset;
}

// Before anything is allocated for it: the accessor's bufferView exists, and its count is
// one a file could mean (a count of billions without data would allocate it all).
Status check_count(const tinygltf::Model& model, const tinygltf::Accessor& acc, int index) {
    if (acc.bufferView >= int(model.bufferViews.size()))
        return make_error(ErrorCode::parse_error, "accessor {}: bufferView {} out of range", index,
                          acc.bufferView);
    if (acc.count > kMaxAccessorElements)
        return make_error(ErrorCode::parse_error, "accessor {}: {} elements (at most {})", index,
                          acc.count, kMaxAccessorElements);
    return {};
}

}  // namespace

Status read_accessor_floats(const tinygltf::Model& model, int index, std::vector<float>& out,
                            int& components) {
    if (index < 0 || index >= int(model.accessors.size()))
        return make_error(ErrorCode::parse_error, "accessor {} out of range", index);
    const tinygltf::Accessor& acc = model.accessors[index];
    components = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    const int comp_bytes = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    if (components <= 0 || comp_bytes <= 0)
        return make_error(ErrorCode::parse_error, "accessor {}: invalid type or componentType",
                          index);
    const std::size_t elem_bytes = std::size_t(components) * comp_bytes;
    if (Status s = check_count(model, acc, index); !s) return s;
    out.assign(acc.count * components, 0.0f);
    if (acc.bufferView >= 0) {
        const int stride = acc.ByteStride(model.bufferViews[acc.bufferView]);
        if (stride <= 0)
            return make_error(ErrorCode::parse_error, "accessor {}: invalid byteStride", index);
        auto base =
            view_data(model, acc.bufferView, acc.byteOffset, acc.count, stride, elem_bytes, index);
        if (!base) return base.error();
        for (std::size_t i = 0; i < acc.count; ++i)
            for (int c = 0; c < components; ++c)
                out[i * components + c] = float(read_component(*base + i * stride + c * comp_bytes,
                                                               acc.componentType, acc.normalized));
    }
    if (acc.sparse.isSparse) {
        const auto& sp = acc.sparse;
        if (sp.count < 0)
            return make_error(ErrorCode::parse_error, "accessor {}: negative sparse count", index);
        const int idx_bytes = tinygltf::GetComponentSizeInBytes(uint32_t(sp.indices.componentType));
        auto idx = view_data(model, sp.indices.bufferView, sp.indices.byteOffset, sp.count,
                             idx_bytes, idx_bytes, index);
        if (!idx) return idx.error();
        auto val = view_data(model, sp.values.bufferView, sp.values.byteOffset, sp.count,
                             elem_bytes, elem_bytes, index);
        if (!val) return val.error();
        for (int k = 0; k < sp.count; ++k) {
            const auto target =
                std::size_t(read_component(*idx + k * idx_bytes, sp.indices.componentType, false));
            if (target >= acc.count)
                return make_error(ErrorCode::parse_error,
                                  "accessor {}: sparse index {} out of range", index, target);
            for (int c = 0; c < components; ++c)
                out[target * components + c] = float(read_component(
                    *val + k * elem_bytes + c * comp_bytes, acc.componentType, acc.normalized));
        }
    }
    return {};
}

Status read_accessor_uints(const tinygltf::Model& model, int index, std::vector<uint32_t>& out) {
    if (index < 0 || index >= int(model.accessors.size()))
        return make_error(ErrorCode::parse_error, "accessor {} out of range", index);
    const tinygltf::Accessor& acc = model.accessors[index];
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return make_error(ErrorCode::parse_error, "accessor {}: indices must be unsigned integers",
                          index);
    const int comp_bytes = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType));
    const int components = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    if (comp_bytes <= 0 || components <= 0)
        return make_error(ErrorCode::parse_error, "accessor {}: invalid type or componentType",
                          index);
    if (Status s = check_count(model, acc, index); !s) return s;
    out.assign(acc.count * components, 0u);
    if (acc.bufferView < 0) return {};
    const int stride = acc.ByteStride(model.bufferViews[acc.bufferView]);
    if (stride <= 0)
        return make_error(ErrorCode::parse_error, "accessor {}: invalid byteStride", index);
    auto base = view_data(model, acc.bufferView, acc.byteOffset, acc.count, stride,
                          std::size_t(comp_bytes) * components, index);
    if (!base) return base.error();
    for (std::size_t i = 0; i < acc.count; ++i)
        for (int c = 0; c < components; ++c)
            out[i * components + c] = uint32_t(
                read_component(*base + i * stride + c * comp_bytes, acc.componentType, false));
    return {};
}

}  // namespace pathfarm
