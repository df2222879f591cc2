// The materials of a World and their mixed pair table: E* of every pair of
// materials, computed when a material is added, so that no step computes it.
#pragma once

#include "laws/hertz.hpp"

#include <cstdint>
#include <numbers>
#include <vector>

namespace wiredem::engine {

/// Elastic properties of a material.
struct Material {
    double youngs_modulus_pa = 10e9;      ///< E [Pa]
    double poisson_ratio = 0.3;           ///< ν
    double density_kg_per_m3 = 7800.0;    ///< ρ [kg/m³]
    friend bool operator==(const Material&, const Material&) = default;
};

/// The plane-strain modulus E/(1−ν²) of a material [Pa].
[[nodiscard]] inline double plane_modulus_pa(const Material& m)
{
    return m.youngs_modulus_pa / (1 - m.poisson_ratio * m.poisson_ratio);
}

/// Mass of a solid sphere, ρ 4/3 π r³ [kg].
[[nodiscard]] inline double sphere_mass_kg(double density_kg_per_m3, double radius_m)
{
    return density_kg_per_m3 * 4.0 / 3.0 * std::numbers::pi * radius_m * radius_m * radius_m;
}

/// Materials by id, with E* of every pair. Materials are only added, never
/// changed: the table stays valid.
class MaterialTable {
public:
    /// Appends a material and its row and column of E*; returns its id.
    std::uint8_t add(const Material& m)
    {
        materials_.push_back(m);
        const std::size_t n = materials_.size();
        std::vector<double> table(n * n);
        for (std::size_t a = 0; a < n; ++a)
            for (std::size_t b = 0; b < n; ++b)
                table[a * n + b] = engine::effective_modulus_pa(materials_[a].youngs_modulus_pa,
                    materials_[a].poisson_ratio, materials_[b].youngs_modulus_pa, materials_[b].poisson_ratio);
        effective_modulus_pa_ = std::move(table);
        return static_cast<std::uint8_t>(n - 1);
    }
    [[nodiscard]] const Material& operator[](std::size_t id) const { return materials_[id]; }
    [[nodiscard]] std::size_t size() const { return materials_.size(); }
    [[nodiscard]] bool empty() const { return materials_.empty(); }
    [[nodiscard]] auto begin() const { return materials_.begin(); }
    [[nodiscard]] auto end() const { return materials_.end(); }
    /// E* of materials a and b [Pa].
    [[nodiscard]] double effective_modulus_pa(std::uint8_t a, std::uint8_t b) const
    {
        return effective_modulus_pa_[a * materials_.size() + b];
    }

private:
    std::vector<Material> materials_;
    std::vector<double> effective_modulus_pa_; ///< size()², row-major
};

} // namespace wiredem::engine
