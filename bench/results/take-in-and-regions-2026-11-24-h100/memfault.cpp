// memcpy of N bytes into: fresh malloc (4K faults), fresh + MADV_HUGEPAGE, prefaulted; 1 and T threads.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sys/mman.h>
#include <thread>
#include <vector>
using C = std::chrono::steady_clock;
static double now() { return std::chrono::duration<double>(C::now().time_since_epoch()).count(); }
static void copyT(char* to, const char* from, size_t n, int T) {
    std::vector<std::thread> th; size_t piece = (n + T - 1) / T;
    for (int t = 0; t < T; ++t) th.emplace_back([=] { size_t a = t * piece; if (a < n) memcpy(to + a, from + a, std::min(piece, n - a)); });
    for (auto& x : th) x.join();
}
int main(int argc, char** argv) {
    size_t n = (argc > 1 ? atol(argv[1]) : 344) << 20;
    char* src = (char*)aligned_alloc(1 << 21, n); memset(src, 1, n);
    for (int T : {1, 4, 16}) {
        for (int mode = 0; mode < 3; ++mode) {
            char* dst = (char*)mmap(nullptr, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
            if (mode == 1) madvise(dst, n, MADV_HUGEPAGE);
            if (mode == 2) memset(dst, 0, n);
            double t0 = now(); copyT(dst, src, n, T); double t = now() - t0;
            printf("threads %2d %-10s %6.1f ms  %5.2f GB/s\n", T, mode == 0 ? "fresh" : mode == 1 ? "hugepage" : "prefaulted", t * 1e3, n / t / 1e9);
            munmap(dst, n);
        }
    }
    // realloc-like growth: 29 appends of n/29 into a vector that doubles (single-thread copy of old content)
    for (int huge = 0; huge < 2; ++huge) {
        double t0 = now(); size_t cap = 0, size = 0; char* buf = nullptr; size_t step = n / 29;
        for (int i = 0; i < 29; ++i) {
            if (size + step > cap) { size_t nc = std::max(size + step, cap * 16 / 10);
                char* nb = (char*)mmap(nullptr, nc, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
                if (huge) madvise(nb, nc, MADV_HUGEPAGE);
                if (size) memcpy(nb, buf, size); if (buf) munmap(buf, cap); buf = nb; cap = nc; }
            copyT(buf + size, src + size, step, 16); size += step;
        }
        printf("growth x1.6 %s: %6.1f ms\n", huge ? "hugepage" : "4K", (now() - t0) * 1e3);
        munmap(buf, cap);
    }
    system("cat /sys/kernel/mm/transparent_hugepage/enabled /sys/kernel/mm/transparent_hugepage/defrag; uname -r");
}
