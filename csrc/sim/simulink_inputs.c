/* What Simulink sends down to the board: seven int16 values, which the course framework keeps
 * in the globals below (the names of its Gen B serial code). A lab file reads them by declaring
 * `extern int SIMU_Var1_fromSIMU_16bit;`; crslab's scenarios write them between ticks (events of
 * kind "simulink", crslab/sim/event_effects.py). On the DSP `int` is 16 bits, so the values stay in
 * int16 range here too. Weak, so a lab file that defines one of these names itself keeps its own. */
__attribute__((weak)) int SIMU_Var1_fromSIMU_16bit = 0;
__attribute__((weak)) int SIMU_Var2_fromSIMU_16bit = 0;
__attribute__((weak)) int SIMU_Var3_fromSIMU_16bit = 0;
__attribute__((weak)) int SIMU_Var4_fromSIMU_16bit = 0;
__attribute__((weak)) int SIMU_Var5_fromSIMU_16bit = 0;
__attribute__((weak)) int SIMU_Var6_fromSIMU_16bit = 0;
__attribute__((weak)) int SIMU_Var7_fromSIMU_16bit = 0;
