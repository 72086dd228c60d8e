# The few F´ framework definitions an FPP model needs before `fpp-to-dict` writes its dictionary:
# the special ports' types (Fw.Cmd, Fw.Tlm, ...) and the configuration types and constants that
# F´'s own `config/` directory defines. A real deployment imports F´'s; this stub keeps the
# example self-contained. The port signatures are left out: a dictionary does not show them.
type FwChanIdType = U32
type FwDpIdType = U32
type FwDpPriorityType = U32
type FwEventIdType = U32
type FwOpcodeType = U32
type FwPacketDescriptorType = U32
type FwTlmPacketizeIdType = U16
type FwSizeType = U32
type FwSizeStoreType = U16
type FwTimeBaseStoreType = U16
type FwTimeContextStoreType = U8
constant FW_FIXED_LENGTH_STRING_SIZE = 256
module Fw {
  port Cmd
  port CmdReg
  port CmdResponse
  port Log
  port LogText
  port Time
  port Tlm
  enum DpState: U8 { UNTRANSMITTED, PARTIAL, TRANSMITTED } default UNTRANSMITTED
  module DpCfg {
    constant CONTAINER_USER_DATA_SIZE = 32
    enum ProcType: U8 { PROC_TYPE_ZERO = 0x01 }
  }
}
