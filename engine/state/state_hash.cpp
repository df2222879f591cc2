#include "state/state_hash.hpp"

#include "core/hash.hpp"
#include "state/world_fields.hpp"

namespace wiredem::engine {

std::uint64_t state_hash(const World& w)
{
    Fnv1a h;
    for_each_field(w, [&](const std::string&, const auto& value, FieldRole role) {
        if (role != FieldRole::state) return;
        const FlatField f = flatten(value);
        const std::uint64_t count = f.is_real ? f.real.size() : f.integer.size();
        h.add_bytes(&count, sizeof count);
        if (f.is_real) h.add(f.real);
        else h.add(f.integer);
    });
    return h.value();
}

} // namespace wiredem::engine
