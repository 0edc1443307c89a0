// Invariant checks for programming errors (STYLE.md §5.1): they log and abort, never throw.
#pragma once

#include <cstdlib>
#include <string_view>

#include <fmt/format.h>

namespace pathfarm::detail {

[[noreturn]] void check_failed(std::string_view file, int line, std::string_view what);

}  // namespace pathfarm::detail

#define PF_CHECK(cond)                                                   \
    do {                                                                 \
        if (!(cond)) [[unlikely]]                                        \
            ::pathfarm::detail::check_failed(__FILE__, __LINE__, #cond); \
    } while (false)

// Prints both operands, as pbrt's CHECK_EQ does; operands must be fmt-formattable.
#define PF_CHECK_OP(a, b, op)                                                   \
    do {                                                                        \
        const auto& pf_a_ = (a);                                                \
        const auto& pf_b_ = (b);                                                \
        if (!(pf_a_ op pf_b_)) [[unlikely]]                                     \
            ::pathfarm::detail::check_failed(                                   \
                __FILE__, __LINE__,                                             \
                fmt::format("{} " #op " {} ({} vs {})", #a, #b, pf_a_, pf_b_)); \
    } while (false)

#define PF_CHECK_EQ(a, b) PF_CHECK_OP(a, b, ==)
#define PF_CHECK_NE(a, b) PF_CHECK_OP(a, b, !=)
#define PF_CHECK_LT(a, b) PF_CHECK_OP(a, b, <)
#define PF_CHECK_LE(a, b) PF_CHECK_OP(a, b, <=)
#define PF_CHECK_GE(a, b) PF_CHECK_OP(a, b, >=)

#ifdef NDEBUG
#define PF_DCHECK(cond) \
    do {                \
    } while (false)
#else
#define PF_DCHECK(cond) PF_CHECK(cond)
#endif
