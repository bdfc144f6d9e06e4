// hymm-options-doc: the module READMEs' key tables, generated from the options declarations.
//   hymm-options-doc                 prints every section's table
//   hymm-options-doc --write ROOT    rewrites the tables in ROOT/modules/*/README.md
//   hymm-options-doc --check ROOT    exit 1 if a README table is missing or out of date
#include <hymm/app/slam_config.h>

#include <iostream>
#include <string>

int main(int argc, char** argv)
{
    try
    {
        const std::string mode = argc > 1 ? argv[1] : "";
        if (mode.empty())
        {
            for (const auto& s : hymm::app::optionSections())
                std::cout << "## [" << s.section << "] (modules/" << s.module << ")\n\n"
                          << hymm::app::readmeBlock(s) << "\n";
            return 0;
        }
        if ((mode != "--write" && mode != "--check") || argc != 3)
        {
            std::cerr << "usage: hymm-options-doc [--write ROOT | --check ROOT]\n";
            return 2;
        }
        const auto stale = hymm::app::syncReadmeTables(argv[2], mode == "--write");
        for (const auto& s : stale)
            std::cout << (mode == "--write" ? "updated: " : "out of date: ") << s << "\n";
        if (mode == "--check" && !stale.empty())
        {
            std::cout << "run: build/bin/hymm-options-doc --write .\n";
            return 1;
        }
        return 0;
    }
    catch (const std::exception& e)
    {
        std::cerr << "hymm-options-doc: error: " << e.what() << "\n";
        return 1;
    }
}
