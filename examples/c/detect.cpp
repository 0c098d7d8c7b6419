// Boundary particles from C++: the C API behind a small RAII class, checked against the CLI.
//
//   c++ -std=c++17 detect.cpp -I crates/boundary-capi/include -L target/debug -lboundary_capi
//   ./a.out labels.csv 0.05 ge depth=4
//
// Reads a CSV written by `boundary detect --output` (columns x, y[, z], boundary, ...),
// labels it with a `Detector` reused over a few "time steps" (with the margin, when the method
// has one), and compares with the file's `boundary` column. Prints one line
// `n=... dim=... boundary=... mismatches=...`; exits 0 iff nothing differs. `cargo xtask test`
// builds and runs it on the public data.
#include <cstdint>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "boundary.h"

namespace {

// Owns a boundary_detector; errors become exceptions carrying the library's message.
class Detector {
public:
    Detector(const std::string &method, const std::string &params) {
        char err[256] = {0};
        handle_ = boundary_detector_new(method.c_str(), params.c_str(), err, sizeof err);
        if (!handle_) throw std::runtime_error(err);
    }
    Detector(const Detector &) = delete;
    Detector &operator=(const Detector &) = delete;
    ~Detector() { boundary_detector_free(handle_); }

    void set_threads(std::size_t threads) {
        char err[256] = {0};
        if (boundary_detector_set_threads(handle_, threads, err, sizeof err) != BOUNDARY_OK)
            throw std::runtime_error(err);
    }

    // Labels (1 boundary, 0 interior) of the particles `xyz` (dim values each).
    std::vector<std::uint8_t> detect(const std::vector<double> &xyz, int dim, double r,
                                     std::vector<double> *margin = nullptr) const {
        const std::size_t n = xyz.size() / static_cast<std::size_t>(dim);
        std::vector<std::uint8_t> labels(n);
        if (margin) margin->resize(n);
        char err[256] = {0};
        const int code = boundary_detector_detect(handle_, xyz.data(), n, dim, r, labels.data(),
                                                  margin ? margin->data() : nullptr, err,
                                                  sizeof err);
        if (code != BOUNDARY_OK)
            throw std::runtime_error("error " + std::to_string(code) + ": " + err);
        return labels;
    }

private:
    boundary_detector *handle_ = nullptr;
};

std::vector<std::string> split(const std::string &line) {
    std::vector<std::string> fields;
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ',')) {
        if (!field.empty() && field.back() == '\r') field.pop_back();
        fields.push_back(field);
    }
    return fields;
}

}  // namespace

int main(int argc, char **argv) try {
    if (argc < 4) {
        std::cerr << "usage: " << argv[0] << " LABELS.csv R METHOD [PARAMS]\n";
        return 2;
    }
    const double r = std::stod(argv[2]);
    const std::string method = argv[3];
    const std::string params = argc > 4 ? argv[4] : "";
    std::ifstream file(argv[1]);
    std::string line;
    if (!file || !std::getline(file, line)) throw std::runtime_error("cannot read the file");
    const auto header = split(line);
    int cx = -1, cy = -1, cz = -1, cb = -1;
    for (int k = 0; k < static_cast<int>(header.size()); ++k) {
        if (header[k] == "x") cx = k;
        if (header[k] == "y") cy = k;
        if (header[k] == "z") cz = k;
        if (header[k] == "boundary") cb = k;
    }
    if (cx < 0 || cy < 0 || cb < 0) throw std::runtime_error("needs columns x, y and boundary");
    const int dim = cz >= 0 ? 3 : 2;
    std::vector<double> xyz;
    std::vector<std::uint8_t> expected;
    while (std::getline(file, line)) {
        const auto f = split(line);
        xyz.push_back(std::stod(f.at(cx)));
        xyz.push_back(std::stod(f.at(cy)));
        if (dim == 3) xyz.push_back(std::stod(f.at(cz)));
        expected.push_back(static_cast<std::uint8_t>(std::stoi(f.at(cb))));
    }

    Detector detector(method, params);
    detector.set_threads(2);
    std::size_t mismatches = 0, count = 0;
    std::vector<double> margin;
    bool has_margin = true;
    for (int step = 0; step < 3; ++step) {
        std::vector<std::uint8_t> labels;
        try {
            labels = detector.detect(xyz, dim, r, has_margin ? &margin : nullptr);
        } catch (const std::runtime_error &e) {
            // A method without a margin says so: ask again without it.
            if (!has_margin) throw;
            has_margin = false;
            labels = detector.detect(xyz, dim, r);
        }
        count = 0;
        for (std::size_t i = 0; i < labels.size(); ++i) {
            mismatches += labels[i] != expected[i];
            count += labels[i];
        }
    }
    std::cout << "n=" << expected.size() << " dim=" << dim << " boundary=" << count
              << " mismatches=" << mismatches << " (" << method
              << (has_margin ? ", with margin" : ", no margin") << ")\n";
    return mismatches == 0 ? 0 : 1;
} catch (const std::exception &e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
}
