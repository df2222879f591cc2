// Thin RAII layer over the HDF5 1.10 C API for the engine's result files.
//
// Objects: File (create/truncate, open read-only or read-write) → Group (nested paths,
// intermediate groups created on demand) → Dataset (1-D, or 2-D rows × columns,
// row-major) and ExtendableDataset (rows appended over time, for time series). Groups
// and datasets carry attributes: strings (e.g. units = "Pa"), doubles and 64-bit
// integers. Every numeric dataset is chunked (chunks of about 64 KiB of whole rows,
// never larger than the data) and compressed with shuffle + deflate level 4; an empty
// dataset gets an unlimited row dimension, since HDF5 cannot chunk a fixed extent of 0.
// Strings are stored as variable-length UTF-8 scalars (a job spec verbatim, attributes).
//
// Errors: every failure of an HDF5 call, and every misuse of this API (e.g. a size
// that is not a multiple of the column count), throws Hdf5Error, a std::runtime_error
// whose message names the file, the HDF5 object path, the action and HDF5's own
// reason from its error stack. HDF5's automatic error printing to stderr is switched
// off (H5Eset_auto2) on every thread that uses this layer. Why exceptions and not
// Result: writing a result file is dozens of calls at the end of a job or at a sample,
// outside the step loop, and any failure aborts the whole file; the job runner catches
// std::exception and fails the job. Destructors never throw: they close quietly.
//
// Lifetime: objects are move-only and close their identifier when destroyed. A Group
// or Dataset may outlive the File it came from (HDF5 closes the file once the last
// object in it is closed). Thread safety: the Debian libhdf5 is built thread-safe and
// serialises calls; still, use one File and everything opened from it on one thread
// at a time.
#pragma once

#include "core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wiredem::engine::io {

/// Failure of an HDF5 call or misuse of this layer. what() reads
/// "<file>:<object path>: <action>: <HDF5's reason>".
class Hdf5Error : public std::runtime_error {
public:
    /// @param action       what was being done, e.g. "cannot create dataset"
    /// @param file         file name as given to File
    /// @param object_path  absolute HDF5 path of the object concerned ("/" for the root)
    /// @param reason       HDF5's description from its error stack, or ours
    Hdf5Error(const std::string& action, std::string file, std::string object_path, const std::string& reason);
    /// File name as given to File::create / File::open_*.
    [[nodiscard]] const std::string& file() const noexcept { return file_; }
    /// Absolute HDF5 path of the object the failing call was about.
    [[nodiscard]] const std::string& object_path() const noexcept { return object_path_; }

private:
    std::string file_;
    std::string object_path_;
};

/// Element type stored in the file (little-endian IEEE / two's complement).
enum class ElementType { f64, i32, i64, u32, u64 };

namespace detail {

/// Owns one HDF5 identifier and closes it with the matching H5?close function.
/// Move-only. Used by this layer; exposed so that wrappers can be built from ids.
class Handle {
public:
    /// Signature shared by H5Fclose, H5Gclose, H5Dclose, H5Aclose, ... (herr_t(hid_t)).
    using Closer = int (*)(std::int64_t);

    Handle() = default;
    /// Takes ownership of `id` (must be valid, ≥ 0).
    Handle(std::int64_t id, Closer closer) noexcept : id_(id), closer_(closer) {}
    Handle(Handle&& other) noexcept;
    Handle& operator=(Handle&& other) noexcept;
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() { reset(); }

    /// The raw hid_t, or −1 when empty.
    [[nodiscard]] std::int64_t get() const noexcept { return id_; }
    /// Closes the identifier, ignoring errors, and leaves the handle empty.
    void reset() noexcept;
    /// Gives up ownership without closing; returns the id.
    [[nodiscard]] std::int64_t release() noexcept;

private:
    std::int64_t id_ = -1;
    Closer closer_ = nullptr;
};

} // namespace detail

/// An open group or dataset: something with a path and attributes.
class Object {
public:
    /// Absolute HDF5 path, e.g. "/tests/0/deviatoric_stress_pa".
    [[nodiscard]] const std::string& path() const noexcept { return path_; }
    /// Name of the file the object lives in, as given to File.
    [[nodiscard]] const std::string& file_name() const noexcept { return file_; }
    /// The raw hid_t, for direct calls to the HDF5 C API (still owned by this object).
    [[nodiscard]] std::int64_t id() const noexcept { return handle_.get(); }

    /// Writes (or replaces) a variable-length UTF-8 string attribute, e.g. units = "Pa".
    /// The value must not contain a NUL byte.
    void write_string_attribute(std::string_view name, std::string_view value);
    /// Writes (or replaces) a scalar 64-bit float attribute.
    void write_double_attribute(std::string_view name, double value);
    /// Writes (or replaces) a scalar signed 64-bit integer attribute.
    void write_int_attribute(std::string_view name, std::int64_t value);

    /// Whether an attribute of that name exists on this object.
    [[nodiscard]] bool has_attribute(std::string_view name) const;
    /// Reads a string attribute (variable-length or fixed-length).
    [[nodiscard]] std::string read_string_attribute(std::string_view name) const;
    /// Reads a scalar numeric attribute, converted to double by HDF5.
    [[nodiscard]] double read_double_attribute(std::string_view name) const;
    /// Reads a scalar numeric attribute, converted to int64 by HDF5.
    [[nodiscard]] std::int64_t read_int_attribute(std::string_view name) const;

protected:
    Object(detail::Handle handle, std::string file, std::string path)
        : handle_(std::move(handle))
        , file_(std::move(file))
        , path_(std::move(path))
    {
    }
    ~Object() = default;
    Object(Object&&) noexcept = default;
    Object& operator=(Object&&) noexcept = default;

    detail::Handle handle_;
    std::string file_;
    std::string path_;
};

/// An open dataset: shape and readers.
class Dataset : public Object {
public:
    /// Wraps an open dataset identifier (takes ownership).
    Dataset(detail::Handle handle, std::string file, std::string path)
        : Object(std::move(handle), std::move(file), std::move(path))
    {
    }

    /// Current extent: {} for a scalar, {n} for 1-D, {rows, columns} for 2-D.
    [[nodiscard]] std::vector<std::size_t> shape() const;
    /// All elements in row-major order, converted to double by HDF5.
    [[nodiscard]] std::vector<double> read_doubles() const;
    /// All elements in row-major order, converted to int64 by HDF5 (throws on overflow
    /// of the conversion).
    [[nodiscard]] std::vector<std::int64_t> read_int64s() const;
    /// The text of a scalar (or single-element) string dataset.
    [[nodiscard]] std::string read_string() const;
};

/// A dataset whose first (row) dimension is unlimited: a time series grows by append.
class ExtendableDataset : public Dataset {
public:
    /// Wraps an open dataset identifier with an unlimited first dimension (takes ownership).
    ExtendableDataset(detail::Handle handle, std::string file, std::string path);

    /// Appends whole rows, row-major: any number of values for a 1-D dataset, a multiple
    /// of columns() for a 2-D one. The values are converted to the stored element type.
    void append(std::span<const double> rows);
    void append(std::span<const std::int32_t> rows);  ///< as above
    void append(std::span<const std::int64_t> rows);  ///< as above
    void append(std::span<const std::uint32_t> rows); ///< as above
    void append(std::span<const std::uint64_t> rows); ///< as above
    /// Appends N×3 rows (2-D datasets with 3 columns only).
    void append(std::span<const Vec3> rows);

    /// Current number of rows.
    [[nodiscard]] std::size_t rows() const;
    /// Columns of a 2-D dataset; 1 for a 1-D dataset.
    [[nodiscard]] std::size_t columns() const noexcept { return columns_; }
    /// 1 or 2.
    [[nodiscard]] int rank() const noexcept { return rank_; }

private:
    void append_raw(const void* data, std::int64_t mem_type, std::size_t count);

    int rank_ = 1;
    std::size_t columns_ = 1;
};

/// An open group. Paths given to its members are relative to it (or absolute in the
/// file when they start with '/'); "a/b/c" creates missing intermediate groups.
class Group : public Object {
public:
    /// Wraps an open group identifier (takes ownership).
    Group(detail::Handle handle, std::string file, std::string path)
        : Object(std::move(handle), std::move(file), std::move(path))
    {
    }

    /// Creates a group (and missing intermediate groups). Throws if it exists.
    Group create_group(std::string_view path);
    /// Opens an existing group.
    [[nodiscard]] Group open_group(std::string_view path) const;
    /// Opens the group if it exists, creates it otherwise.
    Group require_group(std::string_view path);
    /// Opens an existing dataset.
    [[nodiscard]] Dataset open_dataset(std::string_view path) const;
    /// Opens an existing dataset with an unlimited first dimension (to append to it).
    [[nodiscard]] ExtendableDataset open_extendable_dataset(std::string_view path) const;
    /// Whether a link of that path exists (every component is checked).
    [[nodiscard]] bool exists(std::string_view path) const;
    /// Names of the direct children (groups, datasets), in ascending byte order.
    [[nodiscard]] std::vector<std::string> child_names() const;

    /// Writes a 1-D dataset of values.size() elements (chunked, deflate level 4).
    Dataset write_dataset(std::string_view name, std::span<const double> values);
    Dataset write_dataset(std::string_view name, std::span<const std::int32_t> values);  ///< as above
    Dataset write_dataset(std::string_view name, std::span<const std::int64_t> values);  ///< as above
    Dataset write_dataset(std::string_view name, std::span<const std::uint32_t> values); ///< as above
    Dataset write_dataset(std::string_view name, std::span<const std::uint64_t> values); ///< as above

    /// Writes a 2-D dataset of values.size()/columns rows × columns, from row-major
    /// values. columns ≥ 1 and must divide values.size().
    Dataset write_dataset(std::string_view name, std::span<const double> values, std::size_t columns);
    Dataset write_dataset(
        std::string_view name, std::span<const std::int32_t> values, std::size_t columns); ///< as above
    Dataset write_dataset(
        std::string_view name, std::span<const std::int64_t> values, std::size_t columns); ///< as above
    Dataset write_dataset(
        std::string_view name, std::span<const std::uint32_t> values, std::size_t columns); ///< as above
    Dataset write_dataset(
        std::string_view name, std::span<const std::uint64_t> values, std::size_t columns); ///< as above

    /// Writes an N×3 double dataset, one row per vector (positions, forces).
    Dataset write_dataset(std::string_view name, std::span<const Vec3> vectors);

    /// Writes a scalar variable-length UTF-8 string dataset (e.g. the job spec JSON
    /// verbatim). Not compressed: HDF5 cannot filter variable-length data. The text
    /// must not contain a NUL byte.
    Dataset write_string_dataset(std::string_view name, std::string_view text);

    /// Creates an empty 1-D dataset with an unlimited length, for a time series.
    ExtendableDataset create_extendable_dataset(std::string_view name, ElementType type);
    /// Creates an empty 2-D dataset of 0 × columns with an unlimited row count.
    ExtendableDataset create_extendable_dataset(std::string_view name, ElementType type, std::size_t columns);
};

/// An open HDF5 file.
class File {
public:
    /// Creates a file, truncating an existing one.
    [[nodiscard]] static File create(const std::filesystem::path& path);
    /// Opens an existing file for reading only.
    [[nodiscard]] static File open_read_only(const std::filesystem::path& path);
    /// Opens an existing file for reading and writing.
    [[nodiscard]] static File open_read_write(const std::filesystem::path& path);
    /// Creates a file that lives in memory only (HDF5's core driver without a
    /// backing store): nothing touches the disk; image() gives its bytes.
    /// `name` only names it in messages.
    [[nodiscard]] static File create_in_memory(const std::filesystem::path& name);

    /// The bytes of the whole file as it would be on disk, flushed first.
    [[nodiscard]] std::string image();

    /// The root group "/" (its attributes are the file's global attributes).
    [[nodiscard]] Group root() const;
    /// Flushes buffered data of the whole file to disk.
    void flush();
    /// Closes the file, reporting errors (the destructor closes quietly instead).
    /// Throws Hdf5Error, leaving the file open, while a group, dataset or
    /// attribute opened through it is still open: HDF5 would keep the file
    /// open, unwritten and locked until that object closes, so a file
    /// "closed" and then renamed could be read half written or refused
    /// ("unable to lock file") by a reader. Close (scope) those objects first.
    void close();
    /// File name as given.
    [[nodiscard]] const std::string& name() const noexcept { return name_; }
    /// The raw hid_t (still owned by this object), −1 once closed.
    [[nodiscard]] std::int64_t id() const noexcept { return handle_.get(); }

private:
    File(detail::Handle handle, std::string name) : handle_(std::move(handle)), name_(std::move(name)) {}

    detail::Handle handle_;
    std::string name_;
};

/// Writes a whole HDF5 file so that no reader ever sees it half written:
/// `write` fills the root group of a new file that replace_file_atomically
/// (io/atomic_file.hpp) then puts in place of `path`. On an exception no
/// partial file is left and the exception passes on.
///
/// The file is built in memory (File::create_in_memory) and its bytes
/// written by write_file_bytes, so that no HDF5 call ever meets a failing
/// disk: a write error (a full disk) is a WriteError, one line naming the
/// reason and `path`, and every HDF5 identifier is closed. (On disk, HDF5's
/// sec2 driver leaves a file whose write failed unclosable: H5Dclose and
/// H5Fclose fail, and the library's exit handler, H5_term_library, then
/// crashes closing them.) The cost: the file's bytes in memory twice, the
/// image and its copy, while it is written.
void write_file_atomically(const std::filesystem::path& path, const std::function<void(Group& root)>& write);


} // namespace wiredem::engine::io
