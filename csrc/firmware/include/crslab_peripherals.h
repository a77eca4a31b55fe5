/* crslab: the C28x peripheral registers that DSP2833x_Device.h's 18 peripheral headers declare
 * (ADC, CPU timers, eCAN, eCAP, DMA, ePWM, eQEP, GPIO, I2C, McBSP, PIE, SPI, SCI, system control,
 * external interrupts and interface), by their real names, so that a lab naming one compiles as
 * on the board. Only the GPIO data registers are emulated (DSP2833x_Device.h defines them in full:
 * the LEDs); the others are declared as incomplete structs, so a lab that reads or writes one of
 * their fields gets a compiler error naming it, never a silent wrong value. The list of names is
 * tests/data/framework_names.toml (read from the real headers). */
#ifndef CRSLAB_PERIPHERALS_H
#define CRSLAB_PERIPHERALS_H

struct ADC_REGS;
struct ADC_RESULT_MIRROR_REGS;
struct DEV_EMU_REGS;
struct CPUTIMER_REGS;
struct CPUTIMER_VARS;
struct ECAN_REGS;
struct ECAN_MBOXES;
struct LAM_REGS;
struct MOTS_REGS;
struct MOTO_REGS;
struct ECAP_REGS;
struct DMA_REGS;
struct EPWM_REGS;
struct EQEP_REGS;
struct GPIO_CTRL_REGS;
struct GPIO_INT_REGS;
struct I2C_REGS;
struct MCBSP_REGS;
struct PIE_CTRL_REGS;
struct PIE_VECT_TABLE;
struct SPI_REGS;
struct SCI_REGS;
struct SYS_CTRL_REGS;
struct CSM_REGS;
struct CSM_PWL;
struct FLASH_REGS;
struct XINTRUPT_REGS;
struct XINTF_REGS;

typedef void (*PINT)(void); /* an interrupt service routine, as the PIE vector table holds */

extern volatile struct ADC_REGS AdcRegs;
extern volatile struct ADC_RESULT_MIRROR_REGS AdcMirror;
extern volatile struct DEV_EMU_REGS DevEmuRegs;
extern volatile struct CPUTIMER_REGS CpuTimer0Regs, CpuTimer1Regs, CpuTimer2Regs;
extern struct CPUTIMER_VARS CpuTimer0, CpuTimer1, CpuTimer2;
extern volatile struct ECAN_REGS ECanaRegs, ECanbRegs;
extern volatile struct ECAN_MBOXES ECanaMboxes, ECanbMboxes;
extern volatile struct LAM_REGS ECanaLAMRegs, ECanbLAMRegs;
extern volatile struct MOTS_REGS ECanaMOTSRegs, ECanbMOTSRegs;
extern volatile struct MOTO_REGS ECanaMOTORegs, ECanbMOTORegs;
extern volatile struct ECAP_REGS ECap1Regs, ECap2Regs, ECap3Regs, ECap4Regs, ECap5Regs, ECap6Regs;
extern volatile struct DMA_REGS DmaRegs;
extern volatile struct EPWM_REGS EPwm1Regs, EPwm2Regs, EPwm3Regs, EPwm4Regs, EPwm5Regs, EPwm6Regs;
extern volatile struct EQEP_REGS EQep1Regs, EQep2Regs;
extern volatile struct GPIO_CTRL_REGS GpioCtrlRegs;
extern volatile struct GPIO_INT_REGS GpioIntRegs;
extern volatile struct I2C_REGS I2caRegs;
extern volatile struct MCBSP_REGS McbspaRegs, McbspbRegs;
extern volatile struct PIE_CTRL_REGS PieCtrlRegs;
extern volatile struct PIE_VECT_TABLE PieVectTable;
extern volatile struct SPI_REGS SpiaRegs;
extern volatile struct SCI_REGS SciaRegs, ScibRegs, ScicRegs;
extern volatile struct SYS_CTRL_REGS SysCtrlRegs;
extern volatile struct CSM_REGS CsmRegs;
extern volatile struct CSM_PWL CsmPwl;
extern volatile struct FLASH_REGS FlashRegs;
extern volatile struct XINTRUPT_REGS XIntruptRegs;
extern volatile struct XINTF_REGS XintfRegs;

/* CPU timers: the framework's 1 ms tick is CPU timer 0; these name its registers' fields */
#define StartCpuTimer0() CpuTimer0Regs.TCR.bit.TSS = 0
#define StopCpuTimer0() CpuTimer0Regs.TCR.bit.TSS = 1
#define ReloadCpuTimer0() CpuTimer0Regs.TCR.bit.TRB = 1
#define ReadCpuTimer0Counter() CpuTimer0Regs.TIM.all
#define ReadCpuTimer0Period() CpuTimer0Regs.PRD.all
#define StartCpuTimer1() CpuTimer1Regs.TCR.bit.TSS = 0
#define StopCpuTimer1() CpuTimer1Regs.TCR.bit.TSS = 1
#define ReloadCpuTimer1() CpuTimer1Regs.TCR.bit.TRB = 1
#define ReadCpuTimer1Counter() CpuTimer1Regs.TIM.all
#define ReadCpuTimer1Period() CpuTimer1Regs.PRD.all
#define StartCpuTimer2() CpuTimer2Regs.TCR.bit.TSS = 0
#define StopCpuTimer2() CpuTimer2Regs.TCR.bit.TSS = 1
#define ReloadCpuTimer2() CpuTimer2Regs.TCR.bit.TRB = 1
#define ReadCpuTimer2Counter() CpuTimer2Regs.TIM.all
#define ReadCpuTimer2Period() CpuTimer2Regs.PRD.all
void InitCpuTimers(void);
void ConfigCpuTimer(struct CPUTIMER_VARS *Timer, float Freq, float Period);

/* PIE acknowledge bits, one per interrupt group */
#define PIEACK_GROUP1 0x0001
#define PIEACK_GROUP2 0x0002
#define PIEACK_GROUP3 0x0004
#define PIEACK_GROUP4 0x0008
#define PIEACK_GROUP5 0x0010
#define PIEACK_GROUP6 0x0020
#define PIEACK_GROUP7 0x0040
#define PIEACK_GROUP8 0x0080
#define PIEACK_GROUP9 0x0100
#define PIEACK_GROUP10 0x0200
#define PIEACK_GROUP11 0x0400
#define PIEACK_GROUP12 0x0800

#endif
