// state_hash covers exactly the fields whose role is state: changing any one
// of them changes the hash, changing anything else does not.
#include "simulation.hpp"
#include "state/state_hash.hpp"
#include "state/world_fields.hpp"
#include "wired_column.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

using namespace wiredem::engine;
using wiredem::engine::test::build_wired_column;

namespace {

/// Changes the first number of the field called `name` in its last bit.
void nudge_field(World& w, const std::string& name)
{
    bool found = false;
    for_each_field(w, [&](const std::string& n, auto& v, FieldRole) {
        if (n != name) return;
        found = true;
        FlatField g = flatten(v);
        bool ok = false;
        if constexpr (std::is_same_v<typename FieldCodec<FieldElement<std::remove_cvref_t<decltype(v)>>>::Number, double>) {
            g.real[0] = g.real[0] == 0.0 ? 1e-300 : std::nextafter(g.real[0], INFINITY);
            ok = unflatten(g.real, g.real.size() / g.columns, v);
        } else {
            g.integer[0] ^= 1;
            ok = unflatten(g.integer, g.integer.size() / g.columns, v);
        }
        ASSERT_TRUE(ok) << n;
    });
    ASSERT_TRUE(found) << name;
}

} // namespace

TEST(StateHash, ChangesWithEveryStateFieldAndOnlyWithThem)
{
    Simulation sim(1);
    build_wired_column(sim.world, Integrator::gear5);
    ASSERT_EQ(sim.run(400).end, RunEnd::completed); // contacts formed and sliding, joints yielded
    const World& base = sim.world;
    const std::uint64_t h0 = state_hash(base);

    // Change the first number of each non-empty field in its last bit (0 becomes
    // 1e-300; an integer flips its lowest bit), one field at a time. The
    // fields are listed first and each changed by name (nudge_field): one
    // walk over the fields per field type, not per pair of types (that was
    // two minutes of compile time).
    std::vector<std::pair<std::string, FieldRole>> fields;
    for_each_field(base, [&](const std::string& name, const auto& value, FieldRole role) {
        const FlatField f = flatten(value);
        if (!f.real.empty() || !f.integer.empty()) fields.emplace_back(name, role);
    });
    std::set<std::string> state_fields;
    std::size_t others = 0;
    for (const auto& [name, role] : fields) {
        World changed = base;
        ASSERT_NO_FATAL_FAILURE(nudge_field(changed, name));
        if (role == FieldRole::state) {
            EXPECT_NE(state_hash(changed), h0) << name << " is state but does not change the hash";
            state_fields.insert(name);
        } else {
            EXPECT_EQ(state_hash(changed), h0) << name << " is not state but changes the hash";
            ++others;
        }
    }
    // What the hash must cover, present (non-empty) in this column.
    for (const char* name : {"dt_s", "time_s", "step_count", "bodies/grain/x0", "bodies/grain/x1", "bodies/grain/x5",
             "bodies/wire/x0", "bodies/membrane/x2", "grain_rotation/w1", "grain_rotation/orientation",
             "contacts/tangential", "contacts/touching", "walls/1/point_m", "walls/1/velocity_m_per_s",
             "wire/rest_angle_rad"}) // the walls' springs are in contacts/tangential
        EXPECT_TRUE(state_fields.count(name)) << name;
    EXPECT_GT(others, 50u);
}

