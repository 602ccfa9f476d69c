#pragma once
// Reader of the public CCD benchmark's query files (Wang et al. 2021; Belgrod et al. 2023), shared by the tests
// and `cdkit_ccd_check`. A query is 8 rows, each one point as exact rationals `x_num,x_den,y_num,y_den,z_num,z_den`:
// 4 points at t = 0, then the same 4 at t = 1 (vertex–face: the vertex, then the face; edge–edge: edge A's two end
// points, then edge B's). The handcrafted set carries the ground truth as a 7th column; the simulation sets keep it
// in ../mma_bool/<name>_mma_bool.json. The rationals are converted to double with GMP and checked to be exact, so a
// query in double is the query the ground truth was computed for.

#include "oracles/ccd_scene.hpp"

#include <cdkit/core/math.hpp>

#include <gmp.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace cdkit::test {

struct CcdQuery {
    std::array<cdkit::Vec3<double>, 8> points;  ///< t = 0: rows 1–4, t = 1: rows 5–8
    bool truth = false;                         ///< exact ground truth: the features touch for some t ∈ [0, 1]
};

struct CcdQueryFile {
    std::string path;
    bool vertex_face = true;  ///< else edge–edge
    std::vector<CcdQuery> queries;
};

namespace detail {

[[noreturn]] inline void ccd_file_error(const std::string& path, std::size_t line, const std::string& why) {
    throw std::runtime_error(path + ":" + std::to_string(line) + ": " + why);
}

/// num/den as the double it must equal exactly; throws if it is not a double.
inline double exact_double(const std::string& num, const std::string& den, const std::string& path, std::size_t line) {
    mpq_t q, back;
    mpq_init(q);
    mpq_init(back);
    const std::string text = num + "/" + den;
    const bool parsed = mpq_set_str(q, text.c_str(), 10) == 0 && mpz_sgn(mpq_denref(q)) != 0;
    double d = 0;
    bool exact = false;
    if (parsed) {
        mpq_canonicalize(q);
        d = mpq_get_d(q);
        mpq_set_d(back, d);
        exact = mpq_equal(q, back) != 0;
    }
    mpq_clear(q);
    mpq_clear(back);
    if (!parsed) ccd_file_error(path, line, "not a rational: " + text);
    if (!exact) ccd_file_error(path, line, "not exactly a double: " + text);
    return d;
}

inline std::vector<std::string> split_fields(const std::string& row) {
    std::vector<std::string> out;
    std::stringstream ss(row);
    std::string field;
    while (std::getline(ss, field, ',')) {
        field.erase(std::remove_if(field.begin(), field.end(), [](unsigned char ch) { return std::isspace(ch); }),
                    field.end());
        out.push_back(field);
    }
    return out;
}

}  // namespace detail

/// Reads one query file; throws std::runtime_error naming the file and line on anything malformed.
inline CcdQueryFile read_ccd_query_file(const std::string& path) {
    namespace fs = std::filesystem;
    CcdQueryFile file;
    file.path = path;
    const fs::path p(path);
    const std::string parent = p.parent_path().filename().string();
    const std::string stem = p.stem().string();
    if (parent == "vertex-face") file.vertex_face = true;
    else if (parent == "edge-edge") file.vertex_face = false;
    else if (stem.size() >= 2 && stem.substr(stem.size() - 2) == "vf") file.vertex_face = true;
    else if (stem.size() >= 2 && stem.substr(stem.size() - 2) == "ee") file.vertex_face = false;
    else throw std::runtime_error(path + ": cannot tell vertex-face from edge-edge (folder or name)");

    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::string row;
    std::size_t line = 0;
    std::vector<bool> truths;
    bool has_truth_column = false;
    CcdQuery q;
    int k = 0;
    while (std::getline(in, row)) {
        ++line;
        if (row.find_first_not_of(" \t\r") == std::string::npos) continue;
        const auto f = detail::split_fields(row);
        if (f.size() != 6 && f.size() != 7) detail::ccd_file_error(path, line, "expected 6 or 7 fields");
        if (line == 1) has_truth_column = f.size() == 7;
        else if ((f.size() == 7) != has_truth_column) detail::ccd_file_error(path, line, "field count changes");
        for (int c = 0; c < 3; ++c) q.points[k][c] = detail::exact_double(f[2 * c], f[2 * c + 1], path, line);
        if (has_truth_column) {
            if (f[6] != "0" && f[6] != "1") detail::ccd_file_error(path, line, "truth is not 0 or 1");
            if (k == 0) q.truth = f[6] == "1";
            else if (q.truth != (f[6] == "1")) detail::ccd_file_error(path, line, "truth differs within a query");
        }
        if (++k == 8) {
            file.queries.push_back(q);
            k = 0;
        }
    }
    if (k != 0) detail::ccd_file_error(path, line, "the last query has fewer than 8 rows");
    if (!has_truth_column) {
        const fs::path truth = p.parent_path().parent_path() / "mma_bool" / (stem + "_mma_bool.json");
        truths = read_bool_array(truth.string());
        if (truths.size() != file.queries.size())
            throw std::runtime_error(truth.string() + ": " + std::to_string(truths.size()) + " answers for " +
                                     std::to_string(file.queries.size()) + " queries in " + path);
        for (std::size_t i = 0; i < truths.size(); ++i) file.queries[i].truth = truths[i];
    }
    return file;
}

/// Every query file under `root` (a file, or a folder searched recursively), sorted.
inline std::vector<std::string> find_ccd_query_files(const std::string& root) {
    namespace fs = std::filesystem;
    std::vector<std::string> out;
    if (fs::is_regular_file(root)) return {root};
    if (!fs::is_directory(root)) throw std::runtime_error(root + ": no such file or folder");
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        if (!e.is_regular_file() || e.path().extension() != ".csv") continue;
        const std::string dir = e.path().parent_path().filename().string();
        if (dir == "vertex-face" || dir == "edge-edge" || dir == "queries") out.push_back(e.path().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

/// ../shared/ccd-data beside the repository, or $CDKIT_CCD_DATA.
inline std::string ccd_data_root(const std::string& source_dir) {
    if (const char* env = std::getenv("CDKIT_CCD_DATA")) return env;
    return source_dir + "/../shared/ccd-data";
}

}  // namespace cdkit::test
