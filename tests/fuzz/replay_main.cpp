/**
 * @file replay_main.cpp
 * @brief Runs a fuzz target's entry point on files, without libFuzzer: the regression
 *        inputs under tests/fuzz/regressions/ and the seed corpora replay in every test
 *        build (and under ASan/UBSan in CI), not only in the clang fuzzing build.
 *
 * Usage: <target>_replay FILE_OR_DIR...   (exit 0 when every input ran)
 */
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv);
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv)
{
    namespace fs = std::filesystem;
    LLVMFuzzerInitialize(&argc, &argv);
    std::vector<fs::path> inputs;
    for (int i = 1; i < argc; ++i)
    {
        const fs::path p = argv[i];
        if (fs::is_directory(p))
        {
            for (const auto& e : fs::recursive_directory_iterator(p))
                if (e.is_regular_file() && e.path().filename() != "README.md")
                    inputs.push_back(e.path());
        }
        else if (fs::is_regular_file(p))
            inputs.push_back(p);
        else
        {
            std::cerr << "replay: no such file or folder '" << p.string() << "'\n";
            return 2;
        }
    }
    for (const auto& p : inputs)
    {
        std::ifstream f(p, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    }
    std::cout << "replay: " << inputs.size() << " inputs ran\n";
    return inputs.empty() ? 1 : 0;
}
