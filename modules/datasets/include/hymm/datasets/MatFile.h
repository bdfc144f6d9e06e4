/**
 * @file MatFile.h
 * @brief Read-only access to numeric variables of MATLAB .mat files (v4/v5, through
 *        libmatio), plus a small v5 writer used by tests and tools.
 *
 * The public datasets HYMM imports (Victoria Park, ACFR car park) ship their raw data
 * as MATLAB v5 files of real numeric matrices in several storage classes (double,
 * uint16, uint32...). Every variable is returned as an Eigen double matrix with
 * MATLAB's row/column layout, so callers never deal with matio types.
 */
#pragma once

#include <Eigen/Core>

#include <string>
#include <utility>
#include <vector>

namespace hymm::datasets
{
class MatFile
{
   public:
    /** Opens `path`; throws std::runtime_error naming the path if it does not exist or
     *  is not a MAT file libmatio can read. */
    explicit MatFile(const std::string& path);
    ~MatFile();
    MatFile(const MatFile&) = delete;
    MatFile& operator=(const MatFile&) = delete;

    const std::string& path() const { return path_; }

    /** Names of all variables in the file. */
    std::vector<std::string> variableNames() const;

    bool hasVariable(const std::string& name) const;

    /** Reads a real numeric (or logical) 2-D variable as doubles. Throws naming the
     *  file and variable if it is missing, complex, sparse, a struct/cell or N-D. */
    Eigen::MatrixXd readMatrix(const std::string& name) const;

    /** Reads a variable that must be a row or column vector (any length >= 0). */
    Eigen::VectorXd readVector(const std::string& name) const;

   private:
    std::string path_;
    void* mat_ = nullptr;  //!< mat_t*, kept opaque so matio stays a private dependency
};

/** Writes the given double matrices as a MATLAB v5 file (uncompressed); throws if the
 *  file cannot be created or a variable cannot be written. */
void writeMatFile(
    const std::string& path, const std::vector<std::pair<std::string, Eigen::MatrixXd>>& vars);

}  // namespace hymm::datasets
