// Highlighting of the textual languages (ST, IL, STL): a CodeMirror stream parser.
import { StreamLanguage } from "@codemirror/language";

const words = (s) => new Set(s.split(/\s+/).filter(Boolean).map((w) => w.toUpperCase()));

const KEYWORDS = words(`
  PROGRAM END_PROGRAM FUNCTION END_FUNCTION FUNCTION_BLOCK END_FUNCTION_BLOCK
  VAR VAR_INPUT VAR_OUTPUT VAR_IN_OUT VAR_TEMP VAR_EXTERNAL VAR_GLOBAL VAR_INST END_VAR
  CONSTANT RETAIN NON_RETAIN PERSISTENT AT TYPE END_TYPE STRUCT END_STRUCT ARRAY OF
  IF THEN ELSIF ELSE END_IF CASE END_CASE FOR TO BY DO END_FOR WHILE END_WHILE REPEAT
  UNTIL END_REPEAT EXIT CONTINUE RETURN JMP AND OR XOR NOT MOD AND_THEN OR_ELSE
  CONFIGURATION END_CONFIGURATION RESOURCE END_RESOURCE ON TASK WITH READ_WRITE READ_ONLY
  STEP END_STEP INITIAL_STEP TRANSITION END_TRANSITION FROM ACTION END_ACTION
  METHOD END_METHOD PROPERTY END_PROPERTY INTERFACE END_INTERFACE EXTENDS IMPLEMENTS
  THIS SUPER PUBLIC PRIVATE PROTECTED INTERNAL ABSTRACT FINAL OVERRIDE REF_TO REF
  POINTER TRUE FALSE NULL
  LD LDN ST STN S R ANDN ORN XORN ADD SUB MUL DIV GT GE EQ NE LE LT JMPC JMPCN CAL
  CALC CALCN RET RETC RETCN
  BEGIN END WHILE DEFINE UNIT CONST LABEL GOTO`);

const TYPES = words(`
  BOOL SINT INT DINT LINT USINT UINT UDINT ULINT BYTE WORD DWORD LWORD REAL LREAL
  TIME LTIME DATE TIME_OF_DAY TOD DATE_AND_TIME DT LDATE LTOD LDT STRING WSTRING CHAR
  WCHAR ANY ANY_NUM ANY_INT ANY_REAL ANY_BIT
  TON TOF TP CTU CTD CTUD R_TRIG F_TRIG SR RS`);

export const iec = StreamLanguage.define({
  name: "iec61131",
  startState: () => ({ comment: 0 }),
  token(stream, state) {
    if (state.comment > 0) {
      while (!stream.eol()) {
        if (stream.match("(*")) state.comment++;
        else if (stream.match("*)")) {
          state.comment--;
          if (state.comment === 0) break;
        } else stream.next();
      }
      return "comment";
    }
    if (stream.eatSpace()) return null;
    if (stream.match("(*")) {
      state.comment = 1;
      return "comment";
    }
    if (stream.match("//")) {
      stream.skipToEnd();
      return "comment";
    }
    if (stream.match(/^\{[^}]*\}/)) return "meta";
    if (stream.match(/^'([^'$]|\$.)*'?/) || stream.match(/^"([^"$]|\$.)*"?/)) return "string";
    if (stream.match(/^%[IQM][XBWDL]?[0-9.]*/i)) return "atom";
    if (stream.match(/^(T|TIME|LT|LTIME|D|DATE|TOD|TIME_OF_DAY|DT|DATE_AND_TIME)#[-0-9a-z_:.#]+/i)) return "number";
    if (stream.match(/^[A-Za-z_][A-Za-z_0-9]*#[-+0-9A-Za-z_.]+/)) return "number";
    if (stream.match(/^(2|8|16)#[0-9A-Fa-f_]+/)) return "number";
    if (stream.match(/^[0-9][0-9_]*(\.[0-9_]+)?([eE][-+]?[0-9]+)?/)) return "number";
    if (stream.match(/^[A-Za-z_][A-Za-z_0-9]*/)) {
      const w = stream.current().toUpperCase();
      if (KEYWORDS.has(w)) return "keyword";
      if (TYPES.has(w)) return "typeName";
      return "variableName";
    }
    if (stream.match(/^(:=|=>|<=|>=|<>|\*\*|[-+*/<>=&:;,.^()[\]])/)) return "operator";
    stream.next();
    return null;
  },
  languageData: { commentTokens: { block: { open: "(*", close: "*)" }, line: "//" } },
});
