// Run at configure time (cmake/Arch.cmake): exits 0 when this processor runs x86-64-v3 code.
// Feature by feature, because clang 14 does not know the "x86-64-v3" level name. F16C, LZCNT
// and MOVBE complete the level; every processor with AVX2, FMA and BMI2 has them.
int main() {
    __builtin_cpu_init();
    bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
              __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2");
    return v3 ? 0 : 1;
}
