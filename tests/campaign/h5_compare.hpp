// Compares two HDF5 files object by object: the same groups and datasets, the
// same values bit for bit (numbers read as doubles, which every stored type
// converts to exactly; strings as text), the same attributes but for those
// named in `ignored` (wall times, thread counts: how a run went, not what it
// computed). Returns the differences, empty when the files agree.
#pragma once

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace wiredem::test {

namespace h5_compare_detail {

struct Visit {
    std::vector<std::string> objects; // "g:/path" or "d:/path"
};

inline herr_t collect(hid_t, const char* name, const H5O_info_t* info, void* data)
{
    auto* v = static_cast<Visit*>(data);
    if (info->type == H5O_TYPE_GROUP) v->objects.push_back(std::string("g:") + name);
    if (info->type == H5O_TYPE_DATASET) v->objects.push_back(std::string("d:") + name);
    return 0;
}

inline std::vector<std::string> attribute_names(hid_t obj)
{
    std::vector<std::string> names;
    H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr,
        [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
            static_cast<std::vector<std::string>*>(data)->push_back(name);
            return 0;
        },
        &names);
    return names;
}

/// The attribute's value as text (strings) or the bytes of its doubles.
inline std::string attribute_value(hid_t obj, const std::string& name)
{
    const hid_t a = H5Aopen(obj, name.c_str(), H5P_DEFAULT);
    const hid_t type = H5Aget_type(a);
    std::string out;
    if (H5Tget_class(type) == H5T_STRING) {
        if (H5Tis_variable_str(type) > 0) {
            char* text = nullptr;
            const hid_t mem = H5Tcopy(type); // same character set: no conversion
            H5Aread(a, mem, &text);
            out = text ? text : "";
            const hid_t space = H5Aget_space(a);
            H5Dvlen_reclaim(mem, space, H5P_DEFAULT, &text);
            H5Sclose(space);
            H5Tclose(mem);
        } else {
            out.resize(H5Tget_size(type));
            H5Aread(a, type, out.data());
        }
    } else {
        const hid_t space = H5Aget_space(a);
        std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(1, H5Sget_simple_extent_npoints(space))));
        H5Aread(a, H5T_NATIVE_DOUBLE, v.data());
        out.assign(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
        H5Sclose(space);
    }
    H5Tclose(type);
    H5Aclose(a);
    return out;
}

inline std::string dataset_value(hid_t file, const std::string& path)
{
    const hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
    const hid_t type = H5Dget_type(d);
    const hid_t space = H5Dget_space(d);
    std::string out;
    if (H5Tget_class(type) == H5T_STRING) {
        char* text = nullptr;
        const hid_t mem = H5Tcopy(type); // same character set: no conversion
        H5Dread(d, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, &text);
        out = text ? text : "";
        H5Dvlen_reclaim(mem, space, H5P_DEFAULT, &text);
        H5Tclose(mem);
    } else {
        const int rank = H5Sget_simple_extent_ndims(space);
        std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
        H5Sget_simple_extent_dims(space, dims.data(), nullptr);
        for (hsize_t x : dims) out += std::to_string(x) + "x";
        std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
        if (!v.empty()) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
        out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(double));
    }
    H5Sclose(space);
    H5Tclose(type);
    H5Dclose(d);
    return out;
}

} // namespace h5_compare_detail

inline std::vector<std::string> h5_differences(
    const std::filesystem::path& a_path, const std::filesystem::path& b_path, const std::set<std::string>& ignored)
{
    using namespace h5_compare_detail;
    std::vector<std::string> diffs;
    const hid_t a = H5Fopen(a_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t b = H5Fopen(b_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (a < 0 || b < 0) {
        diffs.push_back("cannot open " + (a < 0 ? a_path : b_path).string());
    } else {
        Visit va, vb;
        H5Ovisit(a, H5_INDEX_NAME, H5_ITER_INC, collect, &va);
        H5Ovisit(b, H5_INDEX_NAME, H5_ITER_INC, collect, &vb);
        if (va.objects != vb.objects) diffs.push_back("the files hold different groups or datasets");
        for (const std::string& o : va.objects) {
            if (std::find(vb.objects.begin(), vb.objects.end(), o) == vb.objects.end()) continue;
            const std::string path = o.substr(2);
            if (o[0] == 'd' && dataset_value(a, path) != dataset_value(b, path)) diffs.push_back("dataset " + path);
            const hid_t oa = H5Oopen(a, path.c_str(), H5P_DEFAULT), ob = H5Oopen(b, path.c_str(), H5P_DEFAULT);
            const std::vector<std::string> na = attribute_names(oa), nb = attribute_names(ob);
            if (na != nb) diffs.push_back("attributes of " + path + " differ in names");
            for (const std::string& n : na)
                if (!ignored.count(n) && std::find(nb.begin(), nb.end(), n) != nb.end()
                    && attribute_value(oa, n) != attribute_value(ob, n))
                    diffs.push_back("attribute " + n + " of " + path);
            H5Oclose(oa);
            H5Oclose(ob);
        }
    }
    if (a >= 0) H5Fclose(a);
    if (b >= 0) H5Fclose(b);
    return diffs;
}

} // namespace wiredem::test
