function [A, B, C, D] = getss(filename, step)
%GETSS  The state-space model a SPACAR .ltv file holds at one step.
%   SYS = GETSS(FILE) is the state-space model of the first step of FILE.ltv
%   (FILE may name the .ltv itself): SS(A, B, C, D) where the Control System
%   Toolbox (MATLAB) or the control package (Octave) is there, otherwise a
%   struct with the fields a, b, c, d (the names SS objects answer to) and
%   A, B, C, D.
%   SYS = GETSS(FILE, STEP) is that of step STEP (1-based).
%   [A, B, C, D] = GETSS(...) returns the four matrices; D is empty when the
%   file holds no feedthrough (its DFT is 0).
%
%   flexmbd's (matlab/ folder of its repository); it reads the file with
%   GETFRSBF.

  if nargin < 1 || ~ischar(filename)
    error('getss:Arguments', 'use getss(FILE) or getss(FILE, STEP), FILE a name');
  end
  if nargin < 2
    step = 1;
  end
  if numel(filename) < 4 || ~strcmpi(filename(end - 3:end), '.ltv')
    filename = [filename '.ltv'];
  end
  if ~exist(filename, 'file')
    error('getss:FileNotFound', 'SPACAR file %s not found', filename);
  end
  if nargout == 2 || nargout == 3
    error('getss:Outputs', 'ask for one state-space model or for A, B, C and D');
  end
  A = getfrsbf(filename, 'A', step);
  B = getfrsbf(filename, 'B', step);
  C = getfrsbf(filename, 'C', step);
  if getfrsbf(filename, 'DFT')
    D = getfrsbf(filename, 'D', step);
  else
    D = [];
  end
  if nargout <= 1
    A = state_space(A, B, C, D);
  end
end


function sys = state_space(A, B, C, D)
  if isempty(D)
    D = zeros(size(C, 1), size(B, 2));
  end
  if exist('OCTAVE_VERSION', 'builtin')
    have_ss = ~isempty(ver('control')) && ~isempty(pkg('list', 'control'));
    if have_ss
      pkg load control
    end
  else
    have_ss = exist('ss', 'file') == 2 || exist('ss', 'class') == 8;
  end
  if have_ss
    sys = ss(A, B, C, D);
  else
    sys = struct('a', A, 'b', B, 'c', C, 'd', D, 'A', A, 'B', B, 'C', C, 'D', D);
  end
end
