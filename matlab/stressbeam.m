function [stress, elements, largest, extrema] = stressbeam(filename, elements, step, options, sections)
%STRESSBEAM  The largest von Mises stresses of spatial beams of a SPACAR result.
%   [STRESS, ELEMENTS, LARGEST, EXTREMA] = STRESSBEAM(FILE, ELEMENTS, STEP, OPT, SECTIONS)
%   for the beams ELEMENTS (BEAM or BEAMW numbers) of the result FILE.sbd (its
%   model FILE.dat beside it) at step STEP (1-based):
%     STRESS    numel(ELEMENTS) x 2, the largest von Mises stress over the
%               section at each beam's ends p and q [MPa];
%     LARGEST   numel(ELEMENTS) x 1, each beam's largest [MPa];
%     EXTREMA   a struct: max and min of LARGEST [MPa].
%   SECTIONS(k) is beam k's cross-section, as SPACAR Light writes it:
%   CrossSection 'rect' with Dimensions [width thickness], or 'circ' with
%   Dimensions diameter [m]. OPT is accepted for SPACAR's calling form; the
%   stresses are always the sections' outer points.
%
%   flexmbd's (matlab/ folder of its repository): it runs
%   `flexmbd stressbeam FILE STEP --beam ...` (the program the environment
%   variable FLEXMBD names, or flexmbd on the path), so the stresses are
%   flexmbd's own, from the same section formulas as its Python results.

  if nargin < 5
    error('stressbeam:Arguments', 'use stressbeam(FILE, ELEMENTS, STEP, OPT, SECTIONS)');
  end
  if numel(sections) ~= numel(elements)
    error('stressbeam:Arguments', 'give one section per beam (%d beams, %d sections)', ...
          numel(elements), numel(sections));
  end
  program = getenv('FLEXMBD');
  if isempty(program)
    program = 'flexmbd';
  end
  command = sprintf('%s stressbeam %s %d', quoted(program), quoted(filename), round(step));
  for k = 1:numel(elements)
    shape = sections(k).CrossSection;
    sizes = sprintf(' %.17g', sections(k).Dimensions);
    command = sprintf('%s --beam %d %s%s', command, round(elements(k)), shape, sizes);
  end
  [status, output] = system(command);
  if status ~= 0
    error('stressbeam:Failed', 'flexmbd stressbeam stopped (exit status %d): %s', ...
          status, strtrim(output));
  end
  values = sscanf(output, '%f', [3, Inf]).';
  if size(values, 1) ~= numel(elements)
    error('stressbeam:Failed', 'flexmbd stressbeam gave %d lines for %d beams: %s', ...
          size(values, 1), numel(elements), strtrim(output));
  end
  elements = values(:, 1);
  stress = values(:, 2:3) / 1e6;
  largest = max(stress, [], 2);
  extrema = struct('max', max(largest), 'min', min(largest));
end


function text = quoted(word)
  % a word for the shell, in single quotes
  text = ['''' strrep(word, '''', '''"''"''') ''''];
end
